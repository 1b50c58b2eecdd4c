// POSIX line rates by termios constant: the sim-plotter reads the rate its host set on the pty.
#pragma once

#include <termios.h>

#include <utility>

namespace popcut::drivers {

inline constexpr std::pair<int, speed_t> kPosixBauds[] = {
    {300, B300},       {600, B600},         {1200, B1200},       {2400, B2400},
    {4800, B4800},     {9600, B9600},       {19200, B19200},     {38400, B38400},
    {57600, B57600},   {115200, B115200},   {230400, B230400},   {460800, B460800},
    {921600, B921600}, {1000000, B1000000}, {2000000, B2000000}, {4000000, B4000000}};

// 9600 for B9600; 0 for an unknown constant.
inline int baud_of_speed(speed_t speed) {
  for (const auto& [rate, constant] : kPosixBauds) {
    if (constant == speed) return rate;
  }
  return 0;
}

}  // namespace popcut::drivers
