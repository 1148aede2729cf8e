// The image passes' command-line options (cli/post_options.h): their defaults, values and usage errors.
#include "cli/post_options.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <string>
#include <vector>

#include "base/error.h"

namespace fly::cli {
namespace {

// Parses `args` (after the program name) into fresh options.
struct Parsed {
  CLI::App app;
  PostOptions options;
  explicit Parsed(std::vector<std::string> args) {
    addPostOptions(app, options);
    app.allow_extras(false);
    std::reverse(args.begin(), args.end());
    app.parse(args);
  }
};

TEST(PostOptions, OffUnlessAskedFor) {
  Parsed p({});
  EXPECT_FALSE(parseAmbientOcclusion(p.options).enabled);
  EXPECT_EQ(parseBloom(p.options).strength, 0.0f);
}

TEST(PostOptions, ValuesAndDefaults) {
  Parsed ssao({"--ssao"});
  EXPECT_TRUE(parseAmbientOcclusion(ssao.options).enabled);
  EXPECT_EQ(parseAmbientOcclusion(ssao.options).radiusM, 0.5f);
  Parsed radius({"--ssao-radius", "2"});
  EXPECT_TRUE(parseAmbientOcclusion(radius.options).enabled);
  EXPECT_EQ(parseAmbientOcclusion(radius.options).radiusM, 2.0f);
  Parsed bloom({"--bloom"});
  EXPECT_EQ(parseBloom(bloom.options).strength, kDefaultBloomStrength);
  Parsed strength({"--bloom", "0.2", "--bloom-threshold", "4"});
  EXPECT_EQ(parseBloom(strength.options).strength, 0.2f);
  EXPECT_EQ(parseBloom(strength.options).thresholdExposed, 4.0f);
}

TEST(PostOptions, BadValuesAreUsageErrorsNamingTheOption) {
  for (const std::vector<std::string>& args :
       std::vector<std::vector<std::string>>{{"--bloom", "2"},
                                             {"--bloom", "-0.1"},
                                             {"--bloom", "abc"},
                                             {"--bloom", "nan"},
                                             {"--bloom-threshold", "0"}}) {
    Parsed p(args);
    try {
      parseBloom(p.options);
      ADD_FAILURE() << args[0] << " " << args[1] << " was accepted";
    } catch (const UsageError& e) {
      EXPECT_NE(std::string(e.what()).find(args[0]), std::string::npos) << e.what();
    }
  }
  for (const char* r : {"0", "-1", "1e5", "nan"}) {
    Parsed p({"--ssao-radius", r});
    EXPECT_THROW(parseAmbientOcclusion(p.options), UsageError) << r;
  }
}

}  // namespace
}  // namespace fly::cli
