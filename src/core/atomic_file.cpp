#include "core/atomic_file.h"

#include <fcntl.h>
#include <unistd.h>

#include <cerrno>
#include <stdexcept>
#include <string>
#include <system_error>

namespace rt {
namespace {

// "<file>: <what>: <the system's reason>", e.g. "... write failed: No space left on device".
[[noreturn]] void failWithErrno(const std::filesystem::path& target, const std::string& what, int error) {
  throw std::runtime_error(target.string() + ": " + what + ": " + std::system_category().message(error));
}

// Owns a file descriptor; closing is explicit so that its error is seen.
class Descriptor {
 public:
  explicit Descriptor(int fd) : fd_(fd) {}
  Descriptor(const Descriptor&) = delete;
  Descriptor& operator=(const Descriptor&) = delete;
  ~Descriptor() {
    if (fd_ >= 0) ::close(fd_);
  }
  [[nodiscard]] int get() const { return fd_; }
  // close() reports the write-back errors some file systems defer to it (NFS, quota).
  int close() {
    const int result = ::close(fd_);
    fd_ = -1;
    return result;
  }

 private:
  int fd_;
};

// write(2) until everything is written: a short write (a full disk fills
// part of a buffer first) continues, and the next call reports the error.
void writeAll(const std::filesystem::path& target, int fd, std::string_view contents) {
  while (!contents.empty()) {
    const ssize_t written = ::write(fd, contents.data(), contents.size());
    if (written < 0) {
      if (errno == EINTR) continue;
      failWithErrno(target, "write failed", errno);
    }
    contents.remove_prefix(static_cast<std::size_t>(written));
  }
}

}  // namespace

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

namespace {

// An unnamed file in `dir` (O_TMPFILE): a process killed before it is linked
// leaves nothing behind. -1 where the file system has no O_TMPFILE.
int openUnnamed(const std::filesystem::path& dir) {
  return ::open(dir.empty() ? "." : dir.c_str(), O_TMPFILE | O_WRONLY | O_CLOEXEC, 0644);
}

void writeAndFlush(const std::filesystem::path& target, Descriptor& fd, std::string_view contents) {
  writeAll(target, fd.get(), contents);
  // On the disk before the rename: a crash after it finds the whole file, not an empty one.
  if (::fsync(fd.get()) != 0) failWithErrno(target, "cannot flush to disk", errno);
}

// A target that exists and is neither a regular file nor a directory (a
// device such as /dev/null, a FIFO): written in place. Renaming over it
// would replace the device node with a file (as root, /dev/null itself),
// and there is no half-written state of a stream to avoid.
bool isSpecialFile(const std::filesystem::path& target) {
  std::error_code ec;
  const std::filesystem::file_status status = std::filesystem::status(target, ec);
  return !ec && std::filesystem::exists(status) && !std::filesystem::is_regular_file(status) &&
         !std::filesystem::is_directory(status);
}

void writeInPlace(const std::filesystem::path& target, std::string_view contents) {
  Descriptor fd(::open(target.c_str(), O_WRONLY | O_CLOEXEC));
  if (fd.get() < 0) failWithErrno(target, "cannot open for writing", errno);
  writeAll(target, fd.get(), contents);
  if (fd.close() != 0) failWithErrno(target, "cannot close", errno);
}

}  // namespace

void writeFileAtomically(const std::filesystem::path& target, std::string_view contents) {
  if (isSpecialFile(target)) {
    writeInPlace(target, contents);
    return;
  }
  AtomicFile file(target);
  Descriptor unnamed(openUnnamed(target.parent_path()));
  if (unnamed.get() >= 0) {
    writeAndFlush(target, unnamed, contents);
    // Named only now, complete, for the rename.
    const std::string self = "/proc/self/fd/" + std::to_string(unnamed.get());
    if (::linkat(AT_FDCWD, self.c_str(), AT_FDCWD, file.temporaryPath().c_str(), AT_SYMLINK_FOLLOW) != 0) {
      failWithErrno(target, "cannot link the written file", errno);
    }
    if (unnamed.close() != 0) failWithErrno(target, "cannot close", errno);
    file.commit();
    return;
  }
  const int unnamedError = errno;
  // Without O_TMPFILE support: a named temporary (a SIGKILL while it is
  // written leaves it beside the target, never in the target's place).
  if (unnamedError != EOPNOTSUPP && unnamedError != EISDIR && unnamedError != EINVAL) {
    failWithErrno(target, "cannot open for writing", unnamedError);
  }
  Descriptor fd(::open(file.temporaryPath().c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644));
  if (fd.get() < 0) failWithErrno(target, "cannot open for writing", errno);
  writeAndFlush(target, fd, contents);
  if (fd.close() != 0) failWithErrno(target, "cannot close", errno);
  file.commit();
}

}  // namespace rt
