#include "core/atomic_file.h"

#include <fcntl.h>
#include <gtest/gtest.h>
#include <sys/stat.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <sstream>
#include <stdexcept>
#include <string>

namespace rt {
namespace {

namespace fs = std::filesystem;

// A fresh directory per test, removed afterwards.
class AtomicFileTest : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ =
        fs::temp_directory_path() / ("rt-atomic-" + std::to_string(::testing::UnitTest::GetInstance()->random_seed()) +
                                     "-" + ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }

  static std::string read(const fs::path& p) {
    std::ifstream in(p, std::ios::binary);
    std::ostringstream text;
    text << in.rdbuf();
    return text.str();
  }
  [[nodiscard]] std::size_t entries() const {
    return static_cast<std::size_t>(std::distance(fs::directory_iterator(dir_), fs::directory_iterator()));
  }

  fs::path dir_;
};

TEST_F(AtomicFileTest, WritesTheWholeTextAndLeavesNoTemporary) {
  const fs::path target = dir_ / "run.csv";
  writeFileAtomically(target, "a,b\n1,2\n");
  EXPECT_EQ(read(target), "a,b\n1,2\n");
  EXPECT_EQ(entries(), 1u);
}

TEST_F(AtomicFileTest, ReplacesAnExistingFile) {
  const fs::path target = dir_ / "run.csv";
  writeFileAtomically(target, "old contents that are longer\n");
  writeFileAtomically(target, "new\n");
  EXPECT_EQ(read(target), "new\n");
}

// A FIFO (like /dev/null, a special file) is written in place: renaming
// over it would put a regular file where the device node was, which as
// root (CI in a container) turned /dev/null itself into a file.
TEST_F(AtomicFileTest, WritesIntoASpecialFileInsteadOfReplacingIt) {
  const fs::path fifo = dir_ / "stream";
  ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
  const int reader = ::open(fifo.c_str(), O_RDONLY | O_NONBLOCK);  // lets the writer open without blocking
  ASSERT_GE(reader, 0);
  writeFileAtomically(fifo, "a,b\n1,2\n");
  char buffer[64] = {};
  const ssize_t n = ::read(reader, buffer, sizeof buffer);
  ::close(reader);
  EXPECT_EQ(std::string(buffer, n > 0 ? static_cast<std::size_t>(n) : 0u), "a,b\n1,2\n");
  EXPECT_TRUE(fs::is_fifo(fifo)) << "the FIFO was replaced";
  EXPECT_EQ(entries(), 1u) << "no temporary left beside it";
}

// Destroyed without commit() (an exception on the way): the previous file
// stays as it was and the temporary is gone.
TEST_F(AtomicFileTest, UncommittedWriteKeepsThePreviousFile) {
  const fs::path target = dir_ / "run.csv";
  writeFileAtomically(target, "previous\n");
  {
    AtomicFile file(target);
    std::ofstream(file.temporaryPath()) << "half-writ";
    EXPECT_EQ(file.temporaryPath().parent_path(), target.parent_path());
  }
  EXPECT_EQ(read(target), "previous\n");
  EXPECT_EQ(entries(), 1u);
}

TEST_F(AtomicFileTest, UnwritableTargetThrowsNamingTheFileAndWritesNothing) {
  const fs::path target = dir_ / "missing-dir" / "run.csv";
  try {
    writeFileAtomically(target, "x\n");
    FAIL() << "expected an error";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find(target.string()), std::string::npos) << e.what();
  }
  EXPECT_FALSE(fs::exists(target));
  EXPECT_EQ(entries(), 0u);
}

// Root ignores permission bits; a directory that is a regular file stops
// anyone. The error names the file and the system's reason.
TEST_F(AtomicFileTest, ATargetBelowARegularFileNamesTheReason) {
  writeFileAtomically(dir_ / "file", "x\n");
  const fs::path target = dir_ / "file" / "run.csv";
  try {
    writeFileAtomically(target, "a,b\n");
    FAIL() << "expected an error";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find(target.string() + ": cannot open for writing: Not a directory"),
              std::string::npos)
        << e.what();
  }
  EXPECT_EQ(entries(), 1u);
}

// The written file is linked only when complete (O_TMPFILE where the file
// system has it): the directory never shows a temporary after a write.
TEST_F(AtomicFileTest, ATargetThatIsADirectoryIsLeftAloneAndNamed) {
  fs::create_directory(dir_ / "run.csv");
  try {
    writeFileAtomically(dir_ / "run.csv", "a,b\n");
    FAIL() << "expected an error";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("Is a directory"), std::string::npos) << e.what();
  }
  EXPECT_TRUE(fs::is_directory(dir_ / "run.csv"));
  EXPECT_EQ(entries(), 1u);
}

}  // namespace
}  // namespace rt
