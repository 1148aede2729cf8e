#include "base/file_io.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "base/error.h"

namespace fly {
namespace {

namespace fs = std::filesystem;

class FileIoTest : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("fly_file_io_" + std::to_string(::testing::UnitTest::GetInstance()->random_seed()) +
                                        "_" + ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }
  fs::path dir_;
};

std::string messageOf(const fs::path& p) {
  try {
    readInputFile(p, "scene file");
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

TEST_F(FileIoTest, MissingEmptyAndDirectoryAreInputErrorsNamingTheFile) {
  const fs::path missing = dir_ / "nope.json";
  EXPECT_NE(messageOf(missing).find(missing.string() + ": scene file does not exist"), std::string::npos);
  EXPECT_NE(messageOf(dir_).find("is a directory"), std::string::npos);
  const fs::path empty = dir_ / "empty.json";
  std::ofstream(empty).close();
  EXPECT_NE(messageOf(empty).find("is empty (0 bytes)"), std::string::npos);
  EXPECT_NO_THROW(readInputFile(empty, "scene file", /*allowEmpty=*/true));
}

TEST_F(FileIoTest, AtomicWriteReplacesWholeFileAndLeavesNoTemporary) {
  const fs::path p = dir_ / "out.txt";
  writeFileAtomic(p, "first version");
  writeFileAtomic(p, "second");
  EXPECT_EQ(readInputFile(p, "output"), "second");
  size_t files = 0;
  for (const auto& e : fs::directory_iterator(dir_)) files += e.is_regular_file() ? 1 : 0;
  EXPECT_EQ(files, 1u);
}

TEST_F(FileIoTest, AtomicWriteIntoMissingDirectoryThrowsAndCreatesNothing) {
  EXPECT_THROW(writeFileAtomic(dir_ / "no" / "out.txt", "x"), std::runtime_error);
  EXPECT_FALSE(fs::exists(dir_ / "no"));
}

TEST(ErrorTest, InputErrorFormatsLocationMessageAndHint) {
  const InputError e({"scene.json", 4, 7, "/site/latitude"}, "latitude 91 is outside [-90, 90]", "use degrees north");
  EXPECT_STREQ(e.what(), "scene.json:4:7 (at /site/latitude): latitude 91 is outside [-90, 90]\n  hint: use degrees north");
  EXPECT_EQ(InputError({"a.ies", 12}, "bad").location().str(), "a.ies:12");
}

}  // namespace
}  // namespace fly
