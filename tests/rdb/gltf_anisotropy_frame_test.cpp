// A glTF KHR_materials_anisotropy material reaches both engines in one frame (docs/materials-engine.md,
// "Anisotropy"): the tangent of the UV set the normal map reads (glTF generates a file's missing tangents
// from the normal texture's coordinates), else the file's TANGENT, the rotation towards w · n × t, and the
// same converted textures, so that the baker (TraceRdb) and the GL engine (RasterRdb) stretch the lobe along
// one direction.
#include <gtest/gtest.h>

#include <algorithm>

#include "rdb/raster_rdb.h"
#include "rdb/trace_rdb_build.h"
#include "sdb/gltf_import.h"
#include "tests/sdb/gltf_builder.h"

namespace fly::rdb {
namespace {

using json = nlohmann::json;

// A 1 m quad in the plane y = 0 facing +Y, with TEXCOORD_0 = (x, z) and TEXCOORD_1 = (z, x), whose metal
// reads its normal map with UV set 1 and its anisotropy (two directions, 45° and 100°) with UV set 0.
test::GltfBuilder anisotropicQuad(bool withTangents) {
  test::GltfBuilder b;
  const std::vector<float> positions = {0, 0, 0, 1, 0, 0, 1, 0, 1, 0, 0, 1};
  json attributes = {{"POSITION", b.floats(positions, "VEC3")},
                     {"NORMAL", b.floats({0, 1, 0, 0, 1, 0, 0, 1, 0, 0, 1, 0}, "VEC3")},
                     {"TEXCOORD_0", b.floats({0, 0, 1, 0, 1, 1, 0, 1}, "VEC2")},
                     {"TEXCOORD_1", b.floats({0, 0, 0, 1, 1, 1, 1, 0}, "VEC2")}};
  if (withTangents)
    attributes["TANGENT"] = b.floats({1, 0, 0, 1, 1, 0, 0, 1, 1, 0, 0, 1, 1, 0, 0, 1}, "VEC4");
  const auto image = [&](const std::vector<uint8_t>& png) {
    b.append("images", {{"bufferView", b.view(png)}, {"mimeType", "image/png"}});
    return b.append("textures", {{"source", int(b.doc["images"].size() - 1)}});
  };
  const int normal = image(test::png(1, 1, {128, 128, 255}));
  const int directions = image(test::png(2, 1, {218, 218, 255, 105, 253, 200}));
  b.material({{"pbrMetallicRoughness", {{"metallicFactor", 1}, {"roughnessFactor", 0.4}}},
              {"normalTexture", {{"index", normal}, {"texCoord", 1}}},
              {"extensions",
               {{"KHR_materials_anisotropy",
                 {{"anisotropyStrength", 0.7},
                  {"anisotropyRotation", 0.2},
                  {"anisotropyTexture", {{"index", directions}}}}}}}});
  b.mesh(json::array(
      {{{"attributes", attributes}, {"indices", b.indices({0, 3, 2, 0, 2, 1})}, {"material", 0}}}));
  b.node({{"mesh", 0}});
  b.scene({0});
  return b;
}

// The RasterRdb vertex at the position of TraceRdb vertex i.
size_t rasterVertex(const RasterRdb& r, const vec3& p) {
  const auto it = std::find_if(r.positionsM.begin(), r.positionsM.end(),
                               [&](const vec3& q) { return glm::length(q - p) < 1e-6f; });
  EXPECT_NE(it, r.positionsM.end());
  return size_t(it - r.positionsM.begin());
}

TEST(GltfAnisotropyInBothEngines, OneFrameAndTheSameTextures) {
  for (const bool withTangents : {false, true}) {
    SCOPED_TRACE(withTangents ? "TANGENT in the file" : "tangents generated");
    test::TempDir dir;
    anisotropicQuad(withTangents).writeGltf(dir / "quad.gltf");
    sdb::Scene scene;
    sdb::importGltf(scene, dir / "quad.gltf");
    const TraceRdb trace = buildTraceRdb(scene);
    const RasterRdb raster = buildRasterRdb(scene);

    // The frame: the file's tangent (+x), else +u of the normal map's UV set 1, u = z. Its bitangent
    // w · n × t points towards −v (the image's top): with v = x that is −x, so w = −1.
    const vec4 expected = withTangents ? vec4(1, 0, 0, 1) : vec4(0, 0, 1, -1);
    ASSERT_EQ(trace.tangents.size(), trace.positionsM.size());
    ASSERT_EQ(raster.tangents.size(), raster.positionsM.size());
    for (size_t i = 0; i < trace.positionsM.size(); ++i) {
      const vec4 t = trace.tangents[i];
      const vec4 r = raster.tangents[rasterVertex(raster, trace.positionsM[i])];
      EXPECT_NEAR(glm::length(vec3(t) - vec3(expected)), 0.0f, 1e-6f) << "vertex " << i;
      EXPECT_EQ(t.w, expected.w);
      EXPECT_NEAR(glm::length(vec3(r) - vec3(t)), 0.0f, 1e-6f) << "vertex " << i;
      EXPECT_EQ(r.w, t.w);
    }

    // The lobe: the same U, V, rotation and textures, read with the same UV set.
    const auto anisotropic = std::find_if(trace.materials.begin(), trace.materials.end(),
                                          [](const TraceMaterial& m) { return m.isAnisotropic(); });
    ASSERT_NE(anisotropic, trace.materials.end());
    const TraceMaterial& tm = *anisotropic;
    const RasterMaterial& rm = raster.materials[raster.meshes[0].material];
    ASSERT_TRUE(rm.anisotropic);
    EXPECT_EQ(rm.anisotropyU, tm.anisotropyU);
    EXPECT_EQ(rm.anisotropyV, tm.anisotropyV);
    EXPECT_EQ(rm.anisotropyRotationRad, tm.anisotropyRotationRad);
    const std::pair<const TraceTextureSlot*, const RasterTextureRef*> pairs[] = {
        {&tm.anisotropyTexture, &rm.anisotropyTexture},
        {&tm.anisotropyRotationTexture, &rm.anisotropyRotationTexture}};
    for (const auto& [slot, ref] : pairs) {
      ASSERT_TRUE(*slot);
      ASSERT_TRUE(*ref);
      EXPECT_EQ(slot->texCoord, 0u);
      EXPECT_EQ(ref->texCoord, 0u);
      const TraceTexture& a = trace.textures[slot->texture];
      const RasterTexture& b = raster.textures[ref->texture];
      ASSERT_EQ(a.width, 2u);
      ASSERT_EQ(b.width, 2u);
      for (uint32_t k = 0; k < a.width; ++k)
        EXPECT_EQ(a.texels[k * a.channels], b.rgba8[4 * k]) << "texel " << k;
    }
    // The two texels' directions, 45° and 100° from +u, each turned by the 0.2 rad rotation, are the
    // rotations both engines read (red × 2π, modulo the half turn of the lobe's symmetry, within an 8-bit
    // step).
    const TraceTexture& turns = trace.textures[tm.anisotropyRotationTexture.texture];
    const double directions[2] = {std::atan2(2.0 * 218 / 255 - 1, 2.0 * 218 / 255 - 1),
                                  std::atan2(2.0 * 253 / 255 - 1, 2.0 * 105 / 255 - 1)};
    for (int k = 0; k < 2; ++k) {
      const double stored = 2.0 * kPi * turns.texels[size_t(k) * turns.channels] / 255.0;
      EXPECT_LE(std::abs(std::remainder(stored - (0.2 + directions[k]), kPi)), kPi / 255.0 + 1e-9)
          << "texel " << k;
    }
  }
}

}  // namespace
}  // namespace fly::rdb
