// Entry point of the popcut CLI; all behaviour lives in cli_commands.cpp.
#include "cli_commands.h"

int main(int argc, char** argv) { return popcut::cli::run(argc, argv); }
