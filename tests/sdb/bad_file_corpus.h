// The malformed-file corpora of the photometric readers (tests/data/bad/ies, tests/data/bad/eulumdat; header-only:
// the test glob compiles *_test.cpp): each file listed in KIND.expect as "PATH<tab>EXIT CODE<tab>SUBSTRING" must
// fail to load with an InputError that contains SUBSTRING, has a hint and names the file, and every file of
// the folder must be listed, so that none goes untested.
#pragma once

#include <gtest/gtest.h>

#include <cstddef>
#include <filesystem>
#include <fstream>
#include <set>
#include <string>

#include "base/error.h"

namespace fly::sdb::test {

template <class Load>
void checkBadFileCorpus(const std::filesystem::path& badDir, const std::string& kind, size_t atLeast, const Load& load) {
  std::ifstream in(badDir / (kind + ".expect"));
  std::set<std::string> listed;
  std::string line;
  while (std::getline(in, line)) {
    if (line.empty()) continue;
    const size_t tab1 = line.find('\t');
    const size_t tab2 = line.find('\t', tab1 + 1);
    ASSERT_NE(tab2, std::string::npos) << line;
    const std::string path = line.substr(0, tab1), exitCode = line.substr(tab1 + 1, tab2 - tab1 - 1);
    const std::string substring = line.substr(tab2 + 1);
    SCOPED_TRACE(path);
    listed.insert(path);
    EXPECT_EQ(exitCode, std::to_string(kExitBadInput));
    try {
      load(badDir / path);
      ADD_FAILURE() << "no error";
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find(substring), std::string::npos) << e.what();
      EXPECT_FALSE(e.hint().empty()) << e.what();
      EXPECT_EQ(e.location().file, (badDir / path).string());
    }
  }
  for (const std::filesystem::directory_entry& f : std::filesystem::directory_iterator(badDir / kind)) {
    EXPECT_TRUE(listed.count(kind + "/" + f.path().filename().string())) << f.path();
  }
  EXPECT_GE(listed.size(), atLeast);
}

}  // namespace fly::sdb::test
