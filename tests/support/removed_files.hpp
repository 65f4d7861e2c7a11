// Files a test writes, removed when it leaves scope (also when an assertion
// returns early).
#pragma once

#include <filesystem>
#include <initializer_list>
#include <vector>

namespace nearcap::test {

class RemovedFiles {
 public:
  RemovedFiles(std::initializer_list<std::filesystem::path> paths) : paths_(paths) {}
  RemovedFiles(const RemovedFiles&) = delete;
  RemovedFiles& operator=(const RemovedFiles&) = delete;
  ~RemovedFiles() {
    std::error_code ignored;
    for (const auto& p : paths_) std::filesystem::remove(p, ignored);
  }

 private:
  std::vector<std::filesystem::path> paths_;
};

}  // namespace nearcap::test
