#include "core/atomic_file.h"

#include <unistd.h>

#include <fstream>
#include <stdexcept>
#include <string>
#include <system_error>

namespace rt {

AtomicFile::AtomicFile(std::filesystem::path target) : target_(std::move(target)) {
  // The temporary lives beside the target so the rename never crosses file systems.
  temporary_ = target_;
  temporary_ += ".tmp." + std::to_string(::getpid());
}

AtomicFile::~AtomicFile() {
  if (!committed_) {
    std::error_code ignored;
    std::filesystem::remove(temporary_, ignored);
  }
}

void AtomicFile::commit() {
  std::error_code ec;
  std::filesystem::rename(temporary_, target_, ec);
  if (ec) throw std::runtime_error(target_.string() + ": cannot rename temporary file: " + ec.message());
  committed_ = true;
}

void writeFileAtomically(const std::filesystem::path& target, std::string_view contents) {
  AtomicFile file(target);
  {
    std::ofstream out(file.temporaryPath(), std::ios::binary | std::ios::trunc);
    if (!out) throw std::runtime_error(target.string() + ": cannot open for writing");
    out.write(contents.data(), static_cast<std::streamsize>(contents.size()));
    out.flush();
    if (!out) throw std::runtime_error(target.string() + ": write failed");
  }
  file.commit();
}

}  // namespace rt
