#pragma once
#include <filesystem>
#include <string_view>

namespace rt {

// A result file that appears complete or not at all: written under a
// temporary name in the target's directory, renamed over the target on
// commit(), removed if destroyed without a commit.
class AtomicFile {
 public:
  explicit AtomicFile(std::filesystem::path target);
  AtomicFile(const AtomicFile&) = delete;
  AtomicFile& operator=(const AtomicFile&) = delete;
  ~AtomicFile();

  [[nodiscard]] const std::filesystem::path& temporaryPath() const { return temporary_; }
  void commit();

 private:
  std::filesystem::path target_;
  std::filesystem::path temporary_;
  bool committed_ = false;
};

// Writes the whole text through an AtomicFile; throws std::runtime_error naming the file.
void writeFileAtomically(const std::filesystem::path& target, std::string_view contents);

}  // namespace rt
