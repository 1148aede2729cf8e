#include "sdb/eulumdat.h"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <set>
#include <string>
#include <vector>

#include "base/error.h"
#include "base/file_io.h"
#include "base/math.h"
#include "bad_file_corpus.h"

namespace fly::sdb {
namespace {

namespace fs = std::filesystem;

const fs::path kDataDir = FLY_TEST_DATA_DIR;

Eulumdat load(const std::string& name) {
  return loadEulumdat(kDataDir / "eulumdat" / name);
}

std::string readText(const fs::path& path) {
  return readInputFile(path, "test file");
}

std::vector<std::string> splitLines(const std::string& text) {
  std::vector<std::string> lines;
  size_t pos = 0;
  while (pos < text.size()) {
    const size_t end = std::min(text.find('\n', pos), text.size());
    lines.push_back(text.substr(pos, end - pos));
    pos = end + 1;
  }
  return lines;
}

std::string joinLines(const std::vector<std::string>& lines) {
  std::string s;
  for (const std::string& l : lines) s += l + "\n";
  return s;
}

// The hand-written symmetry files (tests/data/eulumdat/isym*.ldt) hold intensities a(C) × b(γ) / 10 cd/klm
// with b = 100, 80, 40, 0 at γ = 0°, 30°, 60°, 90°, and 2000 lm of lamps: candela = a(C) × b(γ) / 10 × 2.
constexpr double kB[] = {100, 80, 40, 0};

// Expects the profile to hold the planes C = 0°, 45°, … 315°, 360° with the factors a(C) given for each.
void expectExpanded(const Eulumdat& e, const std::vector<double>& aPerPlane) {
  const IesProfile& p = e.profile;
  ASSERT_EQ(p.horizontalDeg.size(), 9u);
  ASSERT_EQ(aPerPlane.size(), 9u);
  for (size_t h = 0; h < 9; ++h) {
    EXPECT_EQ(p.horizontalDeg[h], 45.0 * static_cast<double>(h));
    ASSERT_EQ(p.candela[h].size(), 4u);
    for (size_t k = 0; k < 4; ++k) {
      EXPECT_DOUBLE_EQ(p.candela[h][k], aPerPlane[h] * kB[k] / 10.0 * 2.0)
          << "C = " << p.horizontalDeg[h] << "°, γ = " << p.verticalDeg[k] << "°";
    }
  }
}

TEST(Eulumdat, SymmetryTypesExpandToEveryCPlane) {
  {
    SCOPED_TRACE("Isym 0: every plane stored");
    const Eulumdat e = load("isym0-no-symmetry.ldt");
    EXPECT_EQ(e.symmetry, 0);
    expectExpanded(e, {10, 11, 12, 13, 14, 15, 16, 17, 10});
  }
  {
    SCOPED_TRACE("Isym 2: C0–C180 stored, C ↦ 360° − C");
    const Eulumdat e = load("isym2-c0-c180.ldt");
    expectExpanded(e, {10, 11, 12, 13, 14, 13, 12, 11, 10});
  }
  {
    SCOPED_TRACE("Isym 3: C270–C90 stored (through 0°), C ↦ 180° − C");
    const Eulumdat e = load("isym3-c90-c270.ldt");
    // Stored in file order: C270 → 20, C315 → 21, C0 → 22, C45 → 23, C90 → 24.
    expectExpanded(e, {22, 23, 24, 23, 22, 21, 20, 21, 22});
  }
  {
    SCOPED_TRACE("Isym 4: C0–C90 stored, mirrored about both planes");
    const Eulumdat e = load("isym4-both-planes.ldt");
    expectExpanded(e, {10, 11, 12, 11, 10, 11, 12, 11, 10});
  }
  {
    SCOPED_TRACE("Isym 1: one plane, rotationally symmetric");
    const Eulumdat e = load("isym1-rotational.ldt");
    ASSERT_EQ(e.profile.horizontalDeg, std::vector<double>{0.0});
    for (size_t k = 0; k < 4; ++k) EXPECT_DOUBLE_EQ(e.profile.candela[0][k], 10.0 * kB[k] / 10.0 * 2.0);
    // The same intensity in every C-plane.
    for (double c = 0.0; c < 360.0; c += 17.0) {
      EXPECT_DOUBLE_EQ(e.profile.candelaAt(30.0, c), 160.0);
    }
  }
}

TEST(Eulumdat, ExpandedDistributionsHaveTheirSymmetry) {
  // Directions in the light's frame (z = nadir, x = C0, y = C90): the intensity towards (x, y, z) equals the
  // one towards its mirror image about the symmetry plane(s).
  const auto expectMirror = [](const IesProfile& p, bool aboutC0C180, bool aboutC90C270) {
    for (double c = 0.0; c < 360.0; c += 7.3) {
      for (double g = 0.0; g <= 90.0; g += 11.0) {
        const double x = std::sin(degToRad(g)) * std::cos(degToRad(c));
        const double y = std::sin(degToRad(g)) * std::sin(degToRad(c));
        const double z = std::cos(degToRad(g));
        const double i = p.candelaTowards(x, y, z);
        if (aboutC0C180) {
          EXPECT_NEAR(p.candelaTowards(x, -y, z), i, 1e-9 * (1.0 + i)) << c << "° " << g << "°";
        }
        if (aboutC90C270) {
          EXPECT_NEAR(p.candelaTowards(-x, y, z), i, 1e-9 * (1.0 + i)) << c << "° " << g << "°";
        }
      }
    }
  };
  expectMirror(load("isym2-c0-c180.ldt").profile, true, false);
  expectMirror(load("isym3-c90-c270.ldt").profile, false, true);
  expectMirror(load("isym4-both-planes.ldt").profile, true, true);
  // Isym 0's planes differ: its C = 45° and C = 315° differ (a = 11 and 17).
  const IesProfile p0 = load("isym0-no-symmetry.ldt").profile;
  EXPECT_NE(p0.candelaAt(30.0, 45.0), p0.candelaAt(30.0, 315.0));
}

TEST(Eulumdat, FluxByIntegrationMatchesLampFluxTimesLorl) {
  // I(γ) = I₀ cos γ below the horizon emits π I₀: with 1000 lm of lamps and LORL 80 %, I₀ = 800/π cd, which
  // the file tabulates every 5° (rounded to 0.01 cd/klm). The profile's flux integrates the linear
  // interpolation between the 5° samples, which is below the cosine by about 0.06 %.
  const Eulumdat e = load("lambertian-downlight.ldt");
  EXPECT_FALSE(e.absolutePhotometry());
  EXPECT_DOUBLE_EQ(e.profile.lampLumens, 1000.0);
  EXPECT_DOUBLE_EQ(e.lightOutputRatioPercent, 80.0);
  EXPECT_DOUBLE_EQ(e.statedLuminaireFluxLm(), 800.0);
  EXPECT_NEAR(e.profile.totalFluxLm(), 800.0, 0.001 * 800.0);
  EXPECT_NEAR(e.profile.candelaAt(0.0, 0.0), 800.0 / kPi, 0.01);
  EXPECT_EQ(e.profile.candelaAt(120.0, 0.0), 0.0);  // nothing above the horizon

  // The same luminaire measured whole: lamp count −1 (absolute photometry), the luminaire's 800 lm, LORL 100
  // %.
  const Eulumdat a = load("absolute-photometry.ldt");
  EXPECT_TRUE(a.absolutePhotometry());
  EXPECT_EQ(a.lampSets.front().count, -1);
  EXPECT_DOUBLE_EQ(a.statedLuminaireFluxLm(), 800.0);
  EXPECT_NEAR(a.profile.totalFluxLm(), 800.0, 0.001 * 800.0);
  for (size_t k = 0; k < e.profile.verticalDeg.size(); ++k) {
    EXPECT_NEAR(a.profile.candela[0][k], e.profile.candela[0][k], 0.01) << e.profile.verticalDeg[k] << "°";
  }
}

TEST(Eulumdat, EverySymmetryFileIntegratesToItsStatedFlux) {
  // Each hand-written file states LORL = its integrated flux / 2000 lm, rounded to 0.1 %.
  for (const char* name : {"isym0-no-symmetry.ldt", "isym1-rotational.ldt", "isym2-c0-c180.ldt",
                           "isym3-c90-c270.ldt", "isym4-both-planes.ldt"}) {
    SCOPED_TRACE(name);
    const Eulumdat e = load(name);
    EXPECT_NEAR(e.profile.totalFluxLm(), e.statedLuminaireFluxLm(), 0.0005 * 2000.0);
  }
}

TEST(Eulumdat, HeaderFieldsLampSetsAndDecimalCommas) {
  // Two lamp sets in the described layout (six groups of n lines), CRLF line ends, decimal commas.
  const Eulumdat e = load("two-lamp-sets.ldt");
  EXPECT_EQ(e.company, "fly test luminaire, two lamp sets");
  EXPECT_EQ(e.luminaireName, "Twin-lamp batten");
  EXPECT_EQ(e.typeIndicator, 1);
  EXPECT_EQ(e.symmetry, 1);
  EXPECT_DOUBLE_EQ(e.downwardFluxFractionPercent, 95.0);
  EXPECT_DOUBLE_EQ(e.lightOutputRatioPercent, 90.5);
  ASSERT_EQ(e.lampSets.size(), 2u);
  EXPECT_EQ(e.lampSets[0].count, 2);
  EXPECT_EQ(e.lampSets[0].type, "TL-D 36W/830");
  EXPECT_DOUBLE_EQ(e.lampSets[0].totalFluxLm, 6700.0);  // both lamps together
  EXPECT_EQ(e.lampSets[0].colourTemperature, "3000");
  EXPECT_EQ(e.lampSets[0].colourRendering, "1B");
  EXPECT_DOUBLE_EQ(e.lampSets[0].watts, 72.5);
  EXPECT_EQ(e.lampSets[1].type, "TL-D 36W/840");
  EXPECT_EQ(e.lampSets[1].colourTemperature, "4000");
  EXPECT_DOUBLE_EQ(e.lampSets[1].watts, 80.0);
  // The first set's flux converts cd/klm: 300,5 cd/klm × 6.7 klm.
  EXPECT_DOUBLE_EQ(e.profile.lampLumens, 6700.0);
  EXPECT_NEAR(e.profile.candela[0][0], 300.5 * 6.7, 1e-9);
  EXPECT_EQ(e.profile.format, IesFormat::kEulumdat);
  EXPECT_EQ(e.profile.type, PhotometryType::kC);
  EXPECT_NEAR(e.profile.lengthM, 0.1, 1e-12);  // 100 mm
  EXPECT_NE(std::find(e.profile.keywords.begin(), e.profile.keywords.end(), "[LAMP] TL-D 36W/830"),
            e.profile.keywords.end());

  // The same sets written one block of six lines after another, as some software does, read the same.
  std::string text = readText(kDataDir / "eulumdat" / "two-lamp-sets.ldt");
  std::vector<std::string> lines = splitLines(text);
  std::vector<std::string> blocks = lines;
  for (int set = 0; set < 2; ++set) {
    for (int field = 0; field < 6; ++field) blocks[26 + set * 6 + field] = lines[26 + field * 2 + set];
  }
  const Eulumdat b = parseEulumdat(joinLines(blocks), "blocks.ldt");
  ASSERT_EQ(b.lampSets.size(), 2u);
  EXPECT_EQ(b.lampSets[1].type, "TL-D 36W/840");
  EXPECT_DOUBLE_EQ(b.lampSets[0].watts, 72.5);
  EXPECT_EQ(b.profile.candela, e.profile.candela);
}

TEST(Eulumdat, ConversionFactorScalesTheIntensities) {
  std::vector<std::string> lines = splitLines(readText(kDataDir / "eulumdat" / "lambertian-downlight.ldt"));
  const Eulumdat one = parseEulumdat(joinLines(lines), "one.ldt");
  lines[23] = "2.5";
  const Eulumdat scaled = parseEulumdat(joinLines(lines), "scaled.ldt");
  EXPECT_NEAR(scaled.profile.totalFluxLm(), 2.5 * one.profile.totalFluxLm(),
              1e-9 * one.profile.totalFluxLm());
}

TEST(Eulumdat, EveryTruncationIsAnInputErrorAtTheEnd) {
  // Cutting the file after any line gives an input error located at or before the last line kept.
  const std::vector<std::string> lines = splitLines(readText(kDataDir / "eulumdat" / "isym3-c90-c270.ldt"));
  for (size_t keep = 0; keep < lines.size(); ++keep) {
    SCOPED_TRACE(keep);
    const std::vector<std::string> cut(lines.begin(), lines.begin() + static_cast<std::ptrdiff_t>(keep));
    try {
      parseEulumdat(joinLines(cut), "cut.ldt");
      ADD_FAILURE() << "no error";
    } catch (const InputError& e) {
      EXPECT_LE(e.location().line, static_cast<int>(keep)) << e.what();
      EXPECT_FALSE(e.hint().empty());
    }
  }
}

// The messages in eulumdat.expect read "FILE:LINE: message …": the line is part of what is checked.
TEST(EulumdatBadInput, EachFileGivesTheExpectedErrorAtItsLine) {
  test::checkBadFileCorpus(kDataDir / "bad", "eulumdat", 20, [](const fs::path& f) { loadEulumdat(f); });
}

}  // namespace
}  // namespace fly::sdb
