// Rendered card previews held in memory under a byte cap, least recently used dropped first.
#pragma once

#include <cstddef>
#include <list>
#include <mutex>
#include <optional>
#include <string>
#include <unordered_map>
#include <utility>

namespace popcut::daemon {

// Keys count towards the cap (a posted model is part of its key):
// a slider swept over many jobs cannot fill the memory or the disk.
class PreviewCache {
 public:
  explicit PreviewCache(std::size_t cap_bytes) : cap_bytes_(cap_bytes) {}
  std::optional<std::string> get(const std::string& key) {
    std::lock_guard lock(mutex_);
    const auto it = index_.find(key);
    if (it == index_.end()) return std::nullopt;
    lru_.splice(lru_.begin(), lru_, it->second);
    return it->second->second;
  }
  void put(const std::string& key, const std::string& png) {
    const std::size_t size = key.size() + png.size();
    if (size > cap_bytes_) return;
    std::lock_guard lock(mutex_);
    if (index_.count(key)) return;  // rendered twice at once: the same picture
    lru_.emplace_front(key, png);
    index_[key] = lru_.begin();
    bytes_ += size;
    while (bytes_ > cap_bytes_) {
      bytes_ -= lru_.back().first.size() + lru_.back().second.size();
      index_.erase(lru_.back().first);
      lru_.pop_back();
    }
  }

 private:
  std::mutex mutex_;
  std::list<std::pair<std::string, std::string>> lru_;  // most recent first
  std::unordered_map<std::string, std::list<std::pair<std::string, std::string>>::iterator> index_;
  std::size_t bytes_ = 0;
  const std::size_t cap_bytes_;
};

}  // namespace popcut::daemon
