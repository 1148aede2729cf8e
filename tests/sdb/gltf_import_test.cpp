#include "sdb/gltf_import.h"

#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <limits>
#include <sstream>

#include "base/error.h"
#include "base/log.h"
#include "gltf_import_fixture.h"
#include "sdb/features.h"

namespace fly::sdb {
namespace {

using json = nlohmann::json;
using test::GltfBuilder;
using test::TempDir;

constexpr int kByte = 5120, kUByte = 5121, kShort = 5122, kUShort = 5123, kUInt = 5125;
const float kNaN = std::numeric_limits<float>::quiet_NaN();
const float kInf = std::numeric_limits<float>::infinity();

// --- Nodes and transforms.

TEST_F(GltfImport, HierarchyOfTrsAndMatrixNodesPlacesVerticesExactly) {
  GltfBuilder b;
  const int mesh = b.triangles(kTriangle, {0, 1, 2}, "Wall");
  const float s45 = std::sqrt(0.5f);
  b.node({{"name", "Root"}, {"translation", {10, 0, 0}}, {"children", {1}}});
  b.node({{"name", "Child"}, {"rotation", {0, 0, s45, s45}}, {"scale", {2, 2, 2}}, {"mesh", mesh}});
  b.node({{"name", "M"}, {"matrix", {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 5, 0, 1}}, {"mesh", mesh}});
  b.scene({0, 2});

  Node site;
  site.name = "site";
  site.parentFromLocal[3] = vec4(0, 0, 100, 1);
  const NodeId parent = scene_.addNode(site).id;
  const GltfImportResult r = import(b, {parent, "house/"});

  ASSERT_EQ(r.roots.size(), 2u);
  const Node& root = scene_.node(r.roots[0]);
  EXPECT_EQ(root.name, "house/Root");
  EXPECT_EQ(root.parent, parent);
  ASSERT_EQ(root.children.size(), 1u);
  const NodeId childId = root.children[0];
  const Node& child = scene_.node(childId);
  const Node& m = scene_.node(r.roots[1]);
  EXPECT_EQ(child.name, "house/Child");
  EXPECT_EQ(m.name, "house/M");
  EXPECT_EQ(m.parent, parent);
  ASSERT_EQ(child.meshes.size(), 1u);
  ASSERT_EQ(m.meshes, child.meshes);  // one shared mesh
  const Mesh& wall = scene_.mesh(child.meshes[0]);
  EXPECT_EQ(wall.name, "house/Wall");

  // T(0,0,100) · T(10,0,0) · R(90° about z) · S(2): (1,0,0) → (2,0,0) → (0,2,0) → (10,2,100).
  const mat4 world = scene_.worldFromLocal(childId);
  expectVec(transformPoint(world, wall.positions[0]), {10, 0, 100});
  expectVec(transformPoint(world, wall.positions[1]), {10, 2, 100});
  expectVec(transformPoint(world, wall.positions[2]), {8, 0, 100});
  expectVec(transformPoint(scene_.worldFromLocal(r.roots[1]), wall.positions[2]), {0, 6, 100});

  EXPECT_TRUE(r.changes.touches(EntityType::kNode));
  EXPECT_TRUE(r.changes.touches(EntityType::kMesh));
  EXPECT_TRUE(r.changes.touches(EntityType::kMaterial));  // the default material
  EXPECT_TRUE(r.warnings.empty());
}

TEST_F(GltfImport, UnnamedEntitiesAreNamedByIndex) {
  GltfBuilder b;
  const int mat = b.material(json::object());
  b.triangles(kTriangle, {}, "", mat);
  b.node({{"mesh", 0}});
  b.scene({0});
  const GltfImportResult r = import(b, {{}, "p/"});
  EXPECT_EQ(scene_.node(r.roots[0]).name, "p/node0");
  EXPECT_EQ(onlyMesh().name, "p/mesh0");
  EXPECT_EQ(onlyMaterialOfMesh().name, "p/material0");
}

TEST_F(GltfImport, FileWithoutScenesImportsEveryParentlessNode) {
  GltfBuilder b;
  b.node({{"name", "a"}, {"children", {2}}});
  b.node({{"name", "b"}});
  b.node({{"name", "c"}});
  const GltfImportResult r = import(b);
  ASSERT_EQ(r.roots.size(), 2u);
  EXPECT_EQ(scene_.node(r.roots[0]).name, "a");
  EXPECT_EQ(scene_.node(r.roots[1]).name, "b");
  EXPECT_EQ(scene_.nodes().size(), 3u);
}

TEST_F(GltfImport, SceneListingAChildImportsItAsARootWithItsOwnTransform) {
  GltfBuilder b;
  const int mesh = b.triangles(kTriangle, {}, "Tile");
  b.node({{"name", "tmpParent"}, {"children", {1}}, {"translation", {5, 0, 0}}});
  b.node({{"name", "tile"}, {"mesh", mesh}, {"translation", {0, 1, 0}}});
  b.scene({1});
  const GltfImportResult r = import(b);
  ASSERT_EQ(r.roots.size(), 1u);
  EXPECT_EQ(scene_.node(r.roots[0]).name, "tile");
  expectVec(transformPoint(scene_.worldFromLocal(r.roots[0]), vec3(0.0f)), vec3(0, 1, 0));
  EXPECT_TRUE(contains(r.warnings,
                       "scene 0 lists node 1 'tile' as a root, but it is a child of node 0; it is "
                       "imported as a root with its own transform"));

  // Listed with its parent (and twice): imported once, under the parent.
  scene_ = Scene();
  b.scene({0, 1, 0});
  const GltfImportResult twice = import(b);
  EXPECT_EQ(twice.roots.size(), 1u);
  EXPECT_EQ(scene_.nodes().size(), 2u);
  EXPECT_TRUE(
      contains(twice.warnings, "an ancestor of it is listed too; it is imported once, under its parent"));
  EXPECT_TRUE(contains(twice.warnings, "scene 0 lists node 0 'tmpParent' twice; it is imported once"));
}

TEST_F(GltfImport, GltfGlbAndExternalBinGiveTheSameMesh) {
  GltfBuilder b;
  b.triangles({0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0}, {0, 1, 2, 0, 2, 3}, "Quad");  // no normals: flat
  b.node({{"mesh", 0}});
  b.scene({0});
  b.writeGltf(dir_ / "a.gltf");
  b.writeGlb(dir_ / "b.glb");
  b.writeGltfWithBin(dir_ / "c.gltf");
  for (const char* name : {"a.gltf", "b.glb", "c.gltf"}) {
    SCOPED_TRACE(name);
    Scene s;
    importGltf(s, dir_ / name);
    ASSERT_EQ(s.meshes().size(), 1u);
    const Mesh& m = s.meshes().begin()->second;
    EXPECT_EQ(m.name, "Quad");
    EXPECT_EQ(m.indices, (std::vector<uint32_t>{0, 1, 2, 3, 4, 5}));
    EXPECT_EQ(m.positions[2], vec3(1, 1, 0));
    EXPECT_EQ(m.positions[5], vec3(0, 1, 0));
  }
}

// --- Accessors.

TEST_F(GltfImport, IntegerAndNormalizedAttributesAreDequantized) {
  GltfBuilder b;
  b.useExtension("KHR_mesh_quantization", true);
  const json attributes = {
      {"POSITION", b.data(std::vector<int16_t>{0, 0, 0, 1000, 0, 0, 0, 1000, -7}, kShort, "VEC3")},
      {"NORMAL", b.data(std::vector<int8_t>{0, 0, 127, 0, 0, 127, 0, 0, 127}, kByte, "VEC3", true)},
      {"TANGENT",
       b.data(std::vector<int8_t>{127, 0, 0, -128, 127, 0, 0, 127, 127, 0, 0, 127}, kByte, "VEC4", true)},
      {"TEXCOORD_0", b.data(std::vector<uint8_t>{0, 255, 128, 64, 255, 0}, kUByte, "VEC2", true)},
      {"TEXCOORD_1", b.data(std::vector<int16_t>{-32768, 32767, 16384, 0, -16384, 1}, kShort, "VEC2", true)},
      {"COLOR_0", b.data(std::vector<uint16_t>{65535, 0, 32768, 65535, 0, 65535, 0, 0, 1, 2, 3, 4}, kUShort,
                         "VEC4", true)}};
  const int indices = b.data(std::vector<uint8_t>{0, 1, 2, 0}, kUByte, "SCALAR");
  b.mesh(json::array({{{"attributes", attributes}, {"indices", indices}}}));
  b.node({{"mesh", 0}});
  b.scene({0});
  import(b);
  const Mesh& m = onlyMesh();
  EXPECT_EQ(m.positions, (std::vector<vec3>{{0, 0, 0}, {1000, 0, 0}, {0, 1000, -7}}));
  EXPECT_EQ(m.normals[0], vec3(0, 0, 1));
  EXPECT_EQ(m.tangents[0], vec4(1, 0, 0, -1));  // −128 / 127 is clamped to −1
  EXPECT_EQ(m.tangents[1], vec4(1, 0, 0, 1));
  EXPECT_EQ(m.uv0[0], vec2(0, 1));
  EXPECT_FLOAT_EQ(m.uv0[1].x, 128.0f / 255.0f);
  EXPECT_FLOAT_EQ(m.uv0[1].y, 64.0f / 255.0f);
  EXPECT_EQ(m.uv1[0], vec2(-1, 1));
  EXPECT_FLOAT_EQ(m.uv1[1].x, 16384.0f / 32767.0f);
  EXPECT_FLOAT_EQ(m.uv1[2].x, -16384.0f / 32767.0f);
  EXPECT_FLOAT_EQ(m.uv1[2].y, 1.0f / 32767.0f);
  EXPECT_EQ(m.colors[0].x, 1.0f);
  EXPECT_FLOAT_EQ(m.colors[0].z, 32768.0f / 65535.0f);
  EXPECT_FLOAT_EQ(m.colors[2].w, 4.0f / 65535.0f);
  EXPECT_EQ(m.indices, (std::vector<uint32_t>{0, 1, 2}));  // the fourth index is an incomplete triangle
  EXPECT_TRUE(contains(logged_, "not a multiple of 3; the last 1 are ignored"));
}

TEST_F(GltfImport, IndicesOfEveryUnsignedTypeAndVec3ColoursAreRead) {
  for (int type : {kUByte, kUShort, kUInt}) {
    SCOPED_TRACE(type);
    GltfBuilder b;
    const int pos = b.floats({0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0}, "VEC3");
    const int col =
        b.data(std::vector<uint8_t>{255, 0, 0, 0, 255, 0, 0, 0, 255, 51, 51, 51}, kUByte, "VEC3", true);
    int idx = -1;
    if (type == kUByte) idx = b.data(std::vector<uint8_t>{0, 1, 2, 0, 2, 3}, type, "SCALAR");
    if (type == kUShort) idx = b.data(std::vector<uint16_t>{0, 1, 2, 0, 2, 3}, type, "SCALAR");
    if (type == kUInt) idx = b.data(std::vector<uint32_t>{0, 1, 2, 0, 2, 3}, type, "SCALAR");
    b.mesh(json::array({{{"attributes", {{"POSITION", pos}, {"COLOR_0", col}}}, {"indices", idx}}}));
    b.node({{"mesh", 0}});
    b.scene({0});
    Scene s;
    b.writeGltf(dir_ / "i.gltf");
    importGltf(s, dir_ / "i.gltf");
    const Mesh& m = s.meshes().begin()->second;
    EXPECT_EQ(m.indices.size(), 6u);  // no normals: flat, 3 vertices per triangle
    EXPECT_EQ(m.positions[5], vec3(0, 1, 0));
    EXPECT_EQ(m.colors[0], vec4(1, 0, 0, 1));  // VEC3 colours are opaque
    EXPECT_FLOAT_EQ(m.colors[5].x, 0.2f);
  }
}

TEST_F(GltfImport, InterleavedBufferViewWithByteStride) {
  GltfBuilder b;
  // Per vertex: position (3 floats) then uv (2 floats): 20 bytes.
  const std::vector<float> interleaved = {0, 0, 0, 0.5f, 0.25f, 2, 0, 0, 1, 0, 0, 3, 0, 0, 1};
  const int view = b.view(interleaved, 20);
  const int pos = b.accessor(view, 5126, 3, "VEC3");
  const int uv = b.accessor(view, 5126, 3, "VEC2", false, 12);
  const int normal = b.floats({0, 0, 1, 0, 0, 1, 0, 0, 1}, "VEC3");
  b.mesh(json::array({{{"attributes", {{"POSITION", pos}, {"TEXCOORD_0", uv}, {"NORMAL", normal}}}}}));
  b.node({{"mesh", 0}});
  b.scene({0});
  import(b);
  const Mesh& m = onlyMesh();
  EXPECT_EQ(m.positions, (std::vector<vec3>{{0, 0, 0}, {2, 0, 0}, {0, 3, 0}}));
  EXPECT_EQ(m.uv0, (std::vector<vec2>{{0.5f, 0.25f}, {1, 0}, {0, 1}}));
  EXPECT_EQ(m.indices, (std::vector<uint32_t>{0, 1, 2}));  // non-indexed: generated
}

TEST_F(GltfImport, SparseAccessorsReplaceElements) {
  GltfBuilder b;
  // Base positions with two wrong vertices, replaced by the sparse values.
  const int base = b.view(std::vector<float>{0, 0, 0, 9, 9, 9, 0, 1, 0, 9, 9, 9});
  const int sparseIdx = b.view(std::vector<uint16_t>{1, 3});
  const int sparseVal = b.view(std::vector<float>{1, 0, 0, 1, 1, 0});
  json pos = {{"bufferView", base},
              {"componentType", 5126},
              {"count", 4},
              {"type", "VEC3"},
              {"sparse",
               {{"count", 2},
                {"indices", {{"bufferView", sparseIdx}, {"componentType", kUShort}}},
                {"values", {{"bufferView", sparseVal}}}}}};
  const int posAcc = b.append("accessors", pos);
  // An accessor with no buffer view is zeros before its sparse values.
  const int zeroIdx = b.view(std::vector<uint8_t>{1, 2, 0, 0});
  const int zeroVal = b.view(std::vector<float>{1, 0, 0, 0, 1, 0});
  json zeros = {{"componentType", 5126},
                {"count", 3},
                {"type", "VEC3"},
                {"sparse",
                 {{"count", 2},
                  {"indices", {{"bufferView", zeroIdx}, {"componentType", kUByte}}},
                  {"values", {{"bufferView", zeroVal}}}}}};
  const int zeroAcc = b.append("accessors", zeros);
  const int normals4 = b.floats({0, 0, 1, 0, 0, 1, 0, 0, 1, 0, 0, 1}, "VEC3");
  const int normals3 = b.floats({0, 0, 1, 0, 0, 1, 0, 0, 1}, "VEC3");
  b.mesh(json::array({{{"attributes", {{"POSITION", posAcc}, {"NORMAL", normals4}}},
                       {"indices", b.indices({0, 1, 3, 0, 3, 2})}}}),
         "Sparse");
  b.mesh(json::array({{{"attributes", {{"POSITION", zeroAcc}, {"NORMAL", normals3}}}}}), "Zeros");
  b.node({{"mesh", 0}});
  b.node({{"mesh", 1}});
  b.scene({0, 1});
  import(b);
  const Mesh& sparse = scene_.mesh(scene_.findMesh("Sparse"));
  EXPECT_EQ(sparse.positions, (std::vector<vec3>{{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {1, 1, 0}}));
  const Mesh& zero = scene_.mesh(scene_.findMesh("Zeros"));
  EXPECT_EQ(zero.positions, (std::vector<vec3>{{0, 0, 0}, {1, 0, 0}, {0, 1, 0}}));
}

// Sparse values replace indices before they are checked against the vertex count (glTF 2.0 §3.6.2.3: the
// accessor's elements are the substituted ones): a base index past the vertices that a sparse value replaces
// is not an error.
TEST_F(GltfImport, SparseIndicesAreSubstitutedBeforeTheRangeCheck) {
  GltfBuilder b;
  const int positions = b.floats({0, 0, 0, 1, 0, 0, 0, 1, 0}, "VEC3");
  const int base = b.view(std::vector<uint16_t>{0, 1, 7});
  const int sparseIdx = b.view(std::vector<uint8_t>{2});
  const int sparseVal = b.view(std::vector<uint16_t>{2});
  json indices = {{"bufferView", base},
                  {"componentType", kUShort},
                  {"count", 3},
                  {"type", "SCALAR"},
                  {"sparse",
                   {{"count", 1},
                    {"indices", {{"bufferView", sparseIdx}, {"componentType", kUByte}}},
                    {"values", {{"bufferView", sparseVal}}}}}};
  const int indexAcc = b.append("accessors", indices);
  b.mesh(json::array({{{"attributes", {{"POSITION", positions}}}, {"indices", indexAcc}}}));
  b.node({{"mesh", 0}});
  b.scene({0});
  import(b);
  const Mesh& m = onlyMesh();
  EXPECT_EQ(m.positions, (std::vector<vec3>{{0, 0, 0}, {1, 0, 0}, {0, 1, 0}}));
  EXPECT_EQ(m.indices, (std::vector<uint32_t>{0, 1, 2}));
}

// --- Topology.

TEST_F(GltfImport, StripsAndFansBecomeTriangleLists) {
  GltfBuilder b;
  const int strip = b.floats({0, 0, 0, 1, 0, 0, 0, 1, 0, 1, 1, 0, 0, 2, 0}, "VEC3");
  const int stripN = b.floats({0, 0, 1, 0, 0, 1, 0, 0, 1, 0, 0, 1, 0, 0, 1}, "VEC3");
  const int fan = b.floats({0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0}, "VEC3");
  const int fanN = b.floats({0, 0, 1, 0, 0, 1, 0, 0, 1, 0, 0, 1}, "VEC3");
  b.mesh(json::array({{{"attributes", {{"POSITION", strip}, {"NORMAL", stripN}}}, {"mode", 5}}}), "Strip");
  b.mesh(json::array({{{"attributes", {{"POSITION", fan}, {"NORMAL", fanN}}},
                       {"indices", b.indices({0, 1, 2, 3})},
                       {"mode", 6}}}),
         "Fan");
  b.node({{"mesh", 0}});
  b.node({{"mesh", 1}});
  b.scene({0, 1});
  import(b);
  // glTF 2.0 §3.7.2.1: strip p_i = {v_i, v_(i+1+i%2), v_(i+2−i%2)}; fan p_i = {v_(i+1), v_(i+2), v_0}.
  EXPECT_EQ(scene_.mesh(scene_.findMesh("Strip")).indices,
            (std::vector<uint32_t>{0, 1, 2, 1, 3, 2, 2, 3, 4}));
  EXPECT_EQ(scene_.mesh(scene_.findMesh("Fan")).indices, (std::vector<uint32_t>{1, 2, 0, 2, 3, 0}));
}

TEST_F(GltfImport, PointAndLinePrimitivesAreSkippedWithAWarning) {
  GltfBuilder b;
  const int pos = b.floats(kTriangle, "VEC3");
  b.mesh(json::array({{{"attributes", {{"POSITION", pos}}}, {"mode", 0}},
                      {{"attributes", {{"POSITION", pos}}}, {"mode", 1}},
                      {{"attributes", {{"POSITION", pos}}}}}),
         "Mixed");
  b.node({{"mesh", 0}});
  b.scene({0});
  const GltfImportResult r = import(b);
  EXPECT_EQ(onlyMesh().name, "Mixed#2");
  EXPECT_TRUE(contains(r.warnings, "skipped mesh 'Mixed' primitive 0: it draws points"));
  EXPECT_TRUE(contains(r.warnings, "skipped mesh 'Mixed' primitive 1: it draws lines"));
}

// --- Normals and geometry repair.

TEST_F(GltfImport, MissingNormalsBecomeFlatNormalsOnSplitVertices) {
  GltfBuilder b;
  // Two triangles folded along the x axis: one in the z = 0 plane (normal +z), one in y = 0 (normal +y).
  const int pos = b.floats({0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1}, "VEC3");
  const int uv = b.floats({0, 0, 1, 0, 0, 1, 1, 1}, "VEC2");
  const int tangent = b.floats({1, 0, 0, 1, 1, 0, 0, 1, 1, 0, 0, 1, 1, 0, 0, 1}, "VEC4");
  b.mesh(json::array({{{"attributes", {{"POSITION", pos}, {"TEXCOORD_0", uv}, {"TANGENT", tangent}}},
                       {"indices", b.indices({0, 1, 2, 0, 3, 1})}}}));
  b.node({{"mesh", 0}});
  b.scene({0});
  import(b);
  const Mesh& m = onlyMesh();
  ASSERT_EQ(m.positions.size(), 6u);
  EXPECT_EQ(m.indices, (std::vector<uint32_t>{0, 1, 2, 3, 4, 5}));
  EXPECT_EQ(m.positions[4], vec3(0, 0, 1));
  EXPECT_EQ(m.uv0[4], vec2(1, 1));
  for (int k = 0; k < 3; ++k) EXPECT_EQ(m.normals[size_t(k)], vec3(0, 0, 1));
  for (int k = 3; k < 6; ++k) EXPECT_EQ(m.normals[size_t(k)], vec3(0, 1, 0));
  // §3.7.2.1: without normals the tangents must be ignored.
  EXPECT_TRUE(m.tangents.empty());
}

TEST_F(GltfImport, ZeroNanAndUnnormalisedNormalsAreRepaired) {
  GltfBuilder b;
  const int pos = b.floats(kTriangle, "VEC3");
  const int normal = b.floats({0, 0, 0, kNaN, 0, 1, 0, 0, 2}, "VEC3");
  b.mesh(json::array({{{"attributes", {{"POSITION", pos}, {"NORMAL", normal}}}}}), "T");
  b.node({{"mesh", 0}});
  b.scene({0});
  const GltfImportResult r = import(b);
  EXPECT_EQ(onlyMesh().normals, (std::vector<vec3>{{0, 0, 1}, {0, 0, 1}, {0, 0, 1}}));
  EXPECT_TRUE(contains(r.warnings, "replaced 2 zero-length or NaN normals in mesh 'T'"));
  EXPECT_TRUE(contains(r.warnings, "renormalised 1 normals in mesh 'T'"));
}

TEST_F(GltfImport, NanPositionsAndDegenerateTrianglesAreDroppedWithWarnings) {
  GltfBuilder b;
  // Triangles: good, NaN vertex, Inf vertex, repeated index, collinear (in x), good.
  b.triangles({0, 0, 0, 1, 0, 0, 0, 1, 0, kNaN, 0, 0, 0, kInf, 0, 2, 0, 0, 3, 0, 0, 1, 1, 0},
              {0, 1, 2, 0, 3, 1, 4, 1, 2, 0, 0, 1, 0, 5, 6, 1, 7, 2}, "Wall");
  b.node({{"mesh", 0}});
  b.scene({0});
  const GltfImportResult r = import(b);
  const Mesh& m = onlyMesh();
  EXPECT_EQ(m.triangleCount(), 2u);
  // Flat normals split the 2 kept triangles into 6 vertices; none of the dropped ones' vertices remain.
  ASSERT_EQ(m.positions.size(), 6u);
  for (const vec3& p : m.positions) EXPECT_TRUE(isFinite(p));
  EXPECT_TRUE(contains(r.warnings, "dropped 2 triangles with NaN or Inf positions in mesh 'Wall'"));
  EXPECT_TRUE(contains(r.warnings, "dropped 2 degenerate triangles in mesh 'Wall'"));
}

TEST_F(GltfImport, IndexedMeshKeepsOnlyTheVerticesItUses) {
  GltfBuilder b;
  const int pos = b.floats({5, 5, 5, 0, 0, 0, 1, 0, 0, 0, 1, 0}, "VEC3");
  const int normal = b.floats({0, 0, 1, 0, 0, 1, 0, 0, 1, 0, 0, 1}, "VEC3");
  b.mesh(json::array(
      {{{"attributes", {{"POSITION", pos}, {"NORMAL", normal}}}, {"indices", b.indices({1, 2, 3})}}}));
  b.node({{"mesh", 0}});
  b.scene({0});
  import(b);
  EXPECT_EQ(onlyMesh().positions, (std::vector<vec3>{{0, 0, 0}, {1, 0, 0}, {0, 1, 0}}));
  EXPECT_EQ(onlyMesh().indices, (std::vector<uint32_t>{0, 1, 2}));
}

TEST_F(GltfImport, MeshWithoutTrianglesLeftIsDropped) {
  GltfBuilder b;
  b.triangles({0, 0, 0, 1, 1, 1, 2, 2, 2}, {}, "Line");
  b.node({{"name", "n"}, {"mesh", 0}});
  b.scene({0});
  const GltfImportResult r = import(b);
  EXPECT_TRUE(scene_.meshes().empty());
  EXPECT_TRUE(scene_.node(r.roots[0]).meshes.empty());
  EXPECT_TRUE(contains(r.warnings, "mesh 'Line' has no triangles left and is dropped"));
}

// glTF 2.0 §3.7.4: a negative determinant of the world transform makes clockwise the front face. The importer
// gives such nodes a copy with reversed winding, so counter-clockwise in world space agrees with the normals.
TEST_F(GltfImport, MirroredNodesGetAReversedWindingCopyOfTheMesh) {
  GltfBuilder b;
  const int pos = b.floats(kTriangle, "VEC3");
  const int normal = b.floats({0, 0, 1, 0, 0, 1, 0, 0, 1}, "VEC3");
  b.mesh(json::array({{{"attributes", {{"POSITION", pos}, {"NORMAL", normal}}}}}), "T");
  b.node({{"name", "plain"}, {"mesh", 0}});
  b.node({{"name", "mirrorX"}, {"scale", {-1, 1, 1}}, {"mesh", 0}});
  b.node({{"name", "mirrorParent"}, {"scale", {-1, 1, 1}}, {"children", {3}}});
  b.node({{"name", "mirroredTwice"}, {"scale", {1, -2, 1}}, {"mesh", 0}});
  b.node({{"name", "mirrorZ"}, {"matrix", {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, -3, 0, 1, 2, 3, 1}}, {"mesh", 0}});
  b.scene({0, 1, 2, 4});
  import(b);
  ASSERT_EQ(scene_.meshes().size(), 2u);
  const MeshId original = scene_.node(scene_.findNode("plain")).meshes.at(0);
  const MeshId mirrored = scene_.node(scene_.findNode("mirrorX")).meshes.at(0);
  EXPECT_NE(original, mirrored);
  EXPECT_EQ(scene_.node(scene_.findNode("mirroredTwice")).meshes.at(0), original);  // det > 0 again
  EXPECT_EQ(scene_.node(scene_.findNode("mirrorZ")).meshes.at(0), mirrored);        // the copy is shared
  EXPECT_EQ(scene_.mesh(original).indices, (std::vector<uint32_t>{0, 1, 2}));
  EXPECT_EQ(scene_.mesh(mirrored).indices, (std::vector<uint32_t>{0, 2, 1}));
  EXPECT_EQ(scene_.mesh(mirrored).normals, scene_.mesh(original).normals);
  EXPECT_EQ(scene_.mesh(mirrored).name, "T (mirrored)");

  // A mesh that only mirrored nodes use is added as its mirrored copy alone.
  Scene only;
  GltfBuilder mirroredOnly;
  mirroredOnly.triangles(kTriangle, {}, "T");
  mirroredOnly.node({{"scale", {1, 1, -1}}, {"mesh", 0}});
  mirroredOnly.scene({0});
  mirroredOnly.writeGltf(dir_ / "only.gltf");
  importGltf(only, dir_ / "only.gltf");
  ASSERT_EQ(only.meshes().size(), 1u);
  EXPECT_EQ(only.meshes().begin()->second.name, "T (mirrored)");

  for (const auto& [id, node] : scene_.nodes()) {
    for (MeshId meshId : node.meshes) {
      SCOPED_TRACE(node.name);
      const Mesh& m = scene_.mesh(meshId);
      const mat4 world = scene_.worldFromLocal(id);
      const vec3 a = transformPoint(world, m.positions[m.indices[0]]);
      const vec3 b1 = transformPoint(world, m.positions[m.indices[1]]);
      const vec3 c = transformPoint(world, m.positions[m.indices[2]]);
      const vec3 geometric = glm::cross(b1 - a, c - a);
      const vec3 shading = glm::transpose(glm::inverse(mat3(world))) * m.normals[m.indices[0]];
      EXPECT_GT(glm::dot(geometric, shading), 0.0f);
    }
  }
}

// --- Materials (the conversion documented at the top of gltf_import.cpp).

TEST_F(GltfImport, DielectricMaterial) {
  import(withMaterial({{"name", "Paint"},
                       { "pbrMetallicRoughness",
                         { {"baseColorFactor",
                            { 0.5,
                              0.25,
                              0.125,
                              1 }},
                           {"metallicFactor", 0},
                           { "roughnessFactor",
                             0.3 } } }}));
  const Material& m = onlyMaterialOfMesh();
  EXPECT_EQ(m.name, "Paint");
  expectRgb(m.diffuseColor, {0.5f, 0.25f, 0.125f});
  EXPECT_EQ(m.reflectionModel, ReflectionModel::kFresnel);
  expectRgb(m.reflectionColor, Rgb(1.0f));
  EXPECT_FLOAT_EQ(m.ior, 1.5f);
  EXPECT_FLOAT_EQ(m.reflectionGlossiness, 0.3f);
  expectRgb(m.transmissionColor, Rgb(0.0f));
  expectRgb(m.emissionLuminance, Rgb(0.0f));
  EXPECT_FALSE(m.doubleSided);
  EXPECT_FALSE(onlyMesh().twoSided);
  // White Fresnel reflection takes only F0 = 4 % at normal incidence, so the diffuse survives.
  expectRgb(m.effective().diffuse, Rgb(0.5f, 0.25f, 0.125f) * 0.96f, 1e-5f);
}

TEST_F(GltfImport, MetalReflectsItsBaseColorUniformly) {
  import(withMaterial(
      {{ "pbrMetallicRoughness",
         { {"baseColorFactor",
            { 0.9,
              0.6,
              0.3,
              1 }},
           {"metallicFactor", 1},
           { "roughnessFactor",
             0.2 } } }}));
  const Material& m = onlyMaterialOfMesh();
  EXPECT_EQ(m.reflectionModel, ReflectionModel::kUniform);
  expectRgb(m.reflectionColor, {0.9f, 0.6f, 0.3f});
  expectRgb(m.diffuseColor, Rgb(0.0f));
  EXPECT_FLOAT_EQ(m.reflectionGlossiness, 0.2f);
}

TEST_F(GltfImport, PartlyMetallicMaterialsBlendAtOneHalf) {
  // metallic 0.7 ≥ 0.5: metal, reflection = mix(F0(1.5) = 0.04, base, 0.7), diffuse = 0.3 × base.
  import(withMaterial(
      {{ "pbrMetallicRoughness",
         { {"baseColorFactor",
            { 0.8,
              0.4,
              0.2,
              1 }},
           { "metallicFactor",
             0.7 } } }}));
  const Material& metal = onlyMaterialOfMesh();
  EXPECT_EQ(metal.reflectionModel, ReflectionModel::kUniform);
  expectRgb(metal.reflectionColor, Rgb(0.3f * 0.04f) + 0.7f * Rgb(0.8f, 0.4f, 0.2f), 1e-6f);
  expectRgb(metal.diffuseColor, 0.3f * Rgb(0.8f, 0.4f, 0.2f), 1e-6f);

  // metallic 0.3 < 0.5: dielectric with white Fresnel reflection, diffuse = 0.7 × base.
  Scene other;
  withMaterial({{"pbrMetallicRoughness", {{"baseColorFactor", {0.8, 0.4, 0.2, 1}}, {"metallicFactor", 0.3}}}})
      .writeGltf(dir_ / "d.gltf");
  importGltf(other, dir_ / "d.gltf");
  const Material& dielectric = other.material(other.meshes().begin()->second.material);
  EXPECT_EQ(dielectric.reflectionModel, ReflectionModel::kFresnel);
  expectRgb(dielectric.reflectionColor, Rgb(1.0f));
  expectRgb(dielectric.diffuseColor, 0.7f * Rgb(0.8f, 0.4f, 0.2f), 1e-6f);
  EXPECT_FLOAT_EQ(dielectric.reflectionGlossiness, 1.0f);  // glTF's default roughness
}

TEST_F(GltfImport, IorAndSpecularExtensions) {
  GltfBuilder b = withMaterial(
      {{"pbrMetallicRoughness", {{"metallicFactor", 0}}},
       {"extensions",
        {{"KHR_materials_ior", {{"ior", 1.33}}},
         {"KHR_materials_specular", {{"specularFactor", 0.5}, {"specularColorFactor", {1, 0.5, 2}}}}}}});
  b.useExtension("KHR_materials_ior");
  b.useExtension("KHR_materials_specular");
  const GltfImportResult r = import(b);
  const Material& m = onlyMaterialOfMesh();
  EXPECT_FLOAT_EQ(m.ior, 1.33f);
  expectRgb(m.reflectionColor, {0.5f, 0.25f, 0.5f});  // min(specularColor, 1) × specular
  ASSERT_EQ(r.warnings.size(), 1u);
  EXPECT_NE(r.warnings[0].find("specularColorFactor above 1 is clamped to 1"), std::string::npos);
}

TEST_F(GltfImport, TransmissionAndVolumeExtensions) {
  GltfBuilder b = withMaterial(
      {{"pbrMetallicRoughness",
        {{"baseColorFactor", {1, 0.9, 0.8, 1}}, {"metallicFactor", 0}, {"roughnessFactor", 0.1}}},
       {"extensions",
        {{"KHR_materials_transmission", {{"transmissionFactor", 0.8}}},
         {"KHR_materials_volume",
          {{"thicknessFactor", 0.01}, {"attenuationColor", {0.5, 0.6, 0.7}}, {"attenuationDistance", 2}}}}}});
  import(b);
  const Material& m = onlyMaterialOfMesh();
  expectRgb(m.transmissionColor, Rgb(0.8f, 0.72f, 0.64f));
  EXPECT_FLOAT_EQ(m.transmissionGlossiness, 0.1f);
  expectRgb(m.scatteringColor, {0.5f, 0.6f, 0.7f});
  EXPECT_FLOAT_EQ(m.scatteringDistanceM, 2.0f);
  EXPECT_TRUE(m.isTransmissive());
}

TEST_F(GltfImport, AlphaModesBecomeCoverage) {
  import(withMaterial({{"alphaMode", "BLEND"},
                       { "pbrMetallicRoughness",
                         {
                           { "baseColorFactor",
                             { 0.2,
                               0.4,
                               0.6,
                               0.25 } }
                         } }}));
  const Material& m = onlyMaterialOfMesh();
  EXPECT_EQ(m.alphaMode, AlphaMode::kBlend);
  EXPECT_FLOAT_EQ(m.opacity, 0.25f);
  expectRgb(m.transmissionColor, Rgb(0.0f));  // coverage, not transmission: no Fresnel, no tint
  EXPECT_TRUE(m.hasAlpha());

  Scene other;
  withMaterial({{"name", "Leaf"}, {"alphaMode", "MASK"}, {"alphaCutoff", 0.3}}).writeGltf(dir_ / "mask.gltf");
  const GltfImportResult r = importGltf(other, dir_ / "mask.gltf");
  EXPECT_TRUE(r.warnings.empty());
  const Material& leaf = other.material(other.findMaterial("Leaf"));
  EXPECT_EQ(leaf.alphaMode, AlphaMode::kMask);
  EXPECT_FLOAT_EQ(leaf.alphaCutoff, 0.3f);
  EXPECT_FLOAT_EQ(leaf.opacity, 1.0f);

  Scene bad;
  withMaterial({{"alphaMode", "MASK"}, {"alphaCutoff", 1.5}}).writeGltf(dir_ / "badcutoff.gltf");
  EXPECT_THROW(importGltf(bad, dir_ / "badcutoff.gltf"), InputError);
}

TEST_F(GltfImport, EmissionIsFactorTimesStrengthInCandelaPerSquareMetre) {
  GltfBuilder b =
      withMaterial({{"emissiveFactor", {1, 0.5, 0.25}},
                    {"extensions", {{"KHR_materials_emissive_strength", {{"emissiveStrength", 1000}}}}}});
  import(b);
  expectRgb(onlyMaterialOfMesh().emissionLuminance, {1000, 500, 250});
  EXPECT_FALSE(onlyMaterialOfMesh().emissionDisplay);
  EXPECT_TRUE(onlyMaterialOfMesh().isEmissive());  // a light source
}

// Without KHR_materials_emissive_strength, emissiveFactor is a display colour (a label, a logo): shown at
// the exposure's white by the GL engine, no light source for the baker.
TEST_F(GltfImport, EmissionWithoutStrengthIsADisplayColour) {
  import(withMaterial({{"emissiveFactor", {1, 0.5, 0.25}}}));
  expectRgb(onlyMaterialOfMesh().emissionLuminance, {1, 0.5, 0.25});
  EXPECT_TRUE(onlyMaterialOfMesh().emissionDisplay);
  EXPECT_FALSE(onlyMaterialOfMesh().isEmissive());
  EXPECT_FALSE(computeFeatures(scene_).emissiveSurfaces);
}

TEST_F(GltfImport, DoubleSidedAndDefaultMaterial) {
  GltfBuilder b;
  b.material({{"name", "Glass"}, {"doubleSided", true}});
  const int pos = b.floats(kTriangle, "VEC3");
  b.mesh(json::array({{{"attributes", {{"POSITION", pos}}}, {"material", 0}},
                      {{"attributes", {{"POSITION", pos}}}},
                      {{"attributes", {{"POSITION", pos}}}}}),
         "M");
  b.node({{"mesh", 0}});
  b.scene({0});
  import(b);
  const Mesh& two = scene_.mesh(scene_.findMesh("M#0"));
  EXPECT_TRUE(two.twoSided);
  EXPECT_TRUE(scene_.material(two.material).doubleSided);
  const Mesh& a = scene_.mesh(scene_.findMesh("M#1"));
  const Mesh& c = scene_.mesh(scene_.findMesh("M#2"));
  EXPECT_FALSE(a.twoSided);
  EXPECT_EQ(a.material, c.material);  // the default material is added once
  const Material& def = scene_.material(a.material);
  EXPECT_EQ(def.name, "default");
  EXPECT_EQ(def.diffuseColor, Material{}.diffuseColor);
  EXPECT_EQ(scene_.materials().size(), 2u);
}

// --- Textures.

TEST_F(GltfImport, TexturesAreDecodedOnceAndSharedBetweenMaterials) {
  GltfBuilder b;
  const int tex = addImageTexture(b, test::png(2, 1, {255, 0, 0, 0, 255, 0}));
  b.material({{"name", "A"}, {"pbrMetallicRoughness", {{"baseColorTexture", {{"index", tex}}}}}});
  b.material({{"name", "B"},
              {"pbrMetallicRoughness", {{"baseColorTexture", {{"index", tex}}}}},
              {"emissiveTexture", {{"index", tex}}},
              {"normalTexture", {{"index", tex}, {"scale", 0.5}}}});
  b.triangles(kTriangle, {}, "a", 0);
  b.triangles(kTriangle, {}, "b", 1);
  b.node({{"mesh", 0}});
  b.node({{"mesh", 1}});
  b.scene({0, 1});
  import(b);
  ASSERT_EQ(scene_.textures().size(), 1u);
  const auto& [texId, t] = *scene_.textures().begin();
  EXPECT_EQ(t.name, "checker");
  EXPECT_EQ(t.sourcePath, "<embedded>");
  EXPECT_EQ(t.width, 2);
  EXPECT_EQ(t.height, 1);
  EXPECT_EQ(t.channels, 4);
  EXPECT_EQ(t.bitsPerChannel, 8);
  EXPECT_EQ(t.pixels, (std::vector<uint8_t>{255, 0, 0, 255, 0, 255, 0, 255}));
  const Material& a = scene_.material(scene_.findMaterial("A"));
  const Material& m = scene_.material(scene_.findMaterial("B"));
  EXPECT_EQ(a.diffuseTexture.texture, texId);
  EXPECT_EQ(m.diffuseTexture.texture, texId);
  EXPECT_EQ(m.emissionTexture.texture, texId);
  EXPECT_EQ(m.bumpTexture.texture, texId);
  EXPECT_FLOAT_EQ(m.bumpScale, 0.5f);
}

TEST_F(GltfImport, RoughnessAndTransmissionChannelsBecomeGreyTextures) {
  GltfBuilder b = withMaterial(json::object());
  const int tex = addImageTexture(b, test::png(2, 1, {10, 20, 30, 40, 50, 60}));
  b.doc["materials"][0] = {
      {"name", "Frosted"},
      {"pbrMetallicRoughness", {{"metallicFactor", 0}, {"metallicRoughnessTexture", {{"index", tex}}}}},
      {"extensions",
       {{"KHR_materials_transmission",
         {{"transmissionFactor", 1}, {"transmissionTexture", {{"index", tex}}}}}}}};
  import(b);
  const Material& m = onlyMaterialOfMesh();
  const Texture& rough = scene_.texture(m.reflectionGlossinessTexture.texture);
  EXPECT_EQ(rough.name, "checker (green)");
  EXPECT_EQ(rough.channels, 1);
  EXPECT_EQ(rough.pixels, (std::vector<uint8_t>{20, 50}));
  const Texture& trans = scene_.texture(m.transmissionTexture.texture);
  EXPECT_EQ(trans.name, "checker (red)");
  EXPECT_EQ(trans.pixels, (std::vector<uint8_t>{10, 40}));
  EXPECT_EQ(scene_.textures().size(), 2u);  // the RGBA image itself is not used
}

// A constant blue channel (metalness) scales the metallic factor: blue 0 leaves a dielectric, blue 191 with
// factor 0.8 (metallic 0.6) makes a metal, and neither has a metalness texture.
TEST_F(GltfImport, ConstantTextureMetalnessScalesTheMetallicFactor) {
  GltfBuilder b = withMaterial(json::object());
  const int dielectric = addImageTexture(b, test::png(2, 1, {0, 128, 0, 0, 64, 0}));
  b.doc["materials"][0] = {{"name", "Painted"},
                           {"pbrMetallicRoughness",
                            {{"baseColorFactor", {0.5, 0.5, 0.5, 1}},
                             {"metallicRoughnessTexture", {{"index", dielectric}}}}}};
  import(b);
  const Material& painted = onlyMaterialOfMesh();
  EXPECT_EQ(painted.reflectionModel, ReflectionModel::kFresnel);  // a dielectric: the texture has no metal
  expectRgb(painted.diffuseColor, Rgb(0.5f));
  EXPECT_FALSE(painted.metalnessTexture);

  Scene other;
  GltfBuilder c = withMaterial(json::object());
  const int metal = addImageTexture(c, test::png(2, 1, {0, 128, 191, 0, 64, 191}));
  c.doc["materials"][0] = {{"name", "Metal"},
                           {"pbrMetallicRoughness",
                            {{"baseColorFactor", {0.5, 0.5, 0.5, 1}},
                             {"metallicFactor", 0.8},
                             {"metallicRoughnessTexture", {{"index", metal}}}}}};
  c.writeGltf(dir_ / "metal.gltf");
  importGltf(other, dir_ / "metal.gltf");
  const Material& h = other.material(other.findMaterial("Metal"));
  const float metallic = 0.8f * 191.0f / 255.0f;  // 0.6: a metal
  EXPECT_EQ(h.reflectionModel, ReflectionModel::kUniform);
  expectRgb(h.diffuseColor, Rgb(0.5f * (1.0f - metallic)));
  EXPECT_FALSE(h.metalnessTexture);
}

// A blue channel that varies becomes the metalness texture (one channel, the blue values), with the
// metallic factor as its factor, on the dielectric (Fresnel reflection, the whole base colour as diffuse).
TEST_F(GltfImport, VaryingTextureMetalnessBecomesTheMetalnessTexture) {
  GltfBuilder b = withMaterial(json::object());
  const int half = addImageTexture(b, test::png(2, 1, {0, 128, 0, 0, 128, 255}));
  b.doc["materials"][0] = {{"name", "Striped"},
                           {"pbrMetallicRoughness",
                            {{"baseColorFactor", {0.5, 0.6, 0.7, 1}},
                             {"metallicFactor", 0.8},
                             {"metallicRoughnessTexture", {{"index", half}}}}}};
  import(b);
  const Material& m = onlyMaterialOfMesh();
  EXPECT_EQ(m.reflectionModel, ReflectionModel::kFresnel);
  expectRgb(m.diffuseColor, Rgb(0.5f, 0.6f, 0.7f));
  expectRgb(m.reflectionColor, Rgb(1.0f));
  ASSERT_TRUE(m.metalnessTexture);
  EXPECT_FLOAT_EQ(m.metalnessFactor, 0.8f);
  const Texture& metalness = scene_.texture(m.metalnessTexture.texture);
  EXPECT_EQ(metalness.name, "checker (blue)");
  EXPECT_EQ(metalness.channels, 1);
  EXPECT_EQ(metalness.pixels, (std::vector<uint8_t>{0, 255}));
  ASSERT_TRUE(m.reflectionGlossinessTexture);  // the green channel as before
  EXPECT_EQ(scene_.texture(m.reflectionGlossinessTexture.texture).pixels, (std::vector<uint8_t>{128, 128}));
}

// A metal reflects its base colour texture (sRGB, the same image as the diffuse slot); a dielectric's
// base colour texture tints only its diffuse part.
TEST_F(GltfImport, MetalsReflectTheirBaseColourTexture) {
  GltfBuilder b = withMaterial(json::object());
  const int tex = addImageTexture(b, test::png(2, 1, {200, 100, 50, 10, 20, 30}));
  b.doc["materials"][0] = {{"name", "Gold"},
                           {"pbrMetallicRoughness",
                            {{"baseColorFactor", {0.9, 0.8, 0.7, 1}},
                             {"metallicFactor", 1},
                             {"baseColorTexture", {{"index", tex}}}}}};
  import(b);
  const Material& metal = onlyMaterialOfMesh();
  EXPECT_EQ(metal.reflectionModel, ReflectionModel::kUniform);
  ASSERT_TRUE(metal.reflectionTexture);
  EXPECT_EQ(metal.reflectionTexture.texture, metal.diffuseTexture.texture);
  EXPECT_TRUE(metal.reflectionTextureSrgb);
  expectRgb(metal.reflectionColor, Rgb(0.9f, 0.8f, 0.7f));

  Scene other;
  GltfBuilder c = withMaterial(json::object());
  const int ctex = addImageTexture(c, test::png(2, 1, {200, 100, 50, 10, 20, 30}));
  c.doc["materials"][0] = {{"name", "Paint"},
                           {"pbrMetallicRoughness",
                            {{"metallicFactor", 0}, {"baseColorTexture", {{"index", ctex}}}}}};
  c.writeGltf(dir_ / "paint.gltf");
  importGltf(other, dir_ / "paint.gltf");
  const Material& paint = other.material(other.findMaterial("Paint"));
  EXPECT_TRUE(paint.diffuseTexture);
  EXPECT_FALSE(paint.reflectionTexture);
  EXPECT_FALSE(paint.reflectionTextureSrgb);
}

TEST_F(GltfImport, TextureTransformAndTexCoordOverride) {
  GltfBuilder b = withMaterial(json::object());
  const int tex = addImageTexture(b, test::png(1, 1, {1, 2, 3}));
  b.doc["materials"][0] = {
      {"pbrMetallicRoughness",
       {{"baseColorTexture",
         {{"index", tex},
          {"extensions",
           {{"KHR_texture_transform",
             {{"offset", {0.5, 0.25}}, {"rotation", 1.5}, {"scale", {2, 3}}, {"texCoord", 1}}}}}}}}},
      {"emissiveTexture", {{"index", tex}, {"texCoord", 1}}}};
  b.useExtension("KHR_texture_transform");
  import(b);
  const Material& m = onlyMaterialOfMesh();
  EXPECT_EQ(m.diffuseTexture.texCoord, 1);
  EXPECT_EQ(m.diffuseTexture.transform.offset, vec2(0.5f, 0.25f));
  EXPECT_FLOAT_EQ(m.diffuseTexture.transform.rotationRad, 1.5f);
  EXPECT_EQ(m.diffuseTexture.transform.scale, vec2(2, 3));
  EXPECT_EQ(m.emissionTexture.texCoord, 1);
  EXPECT_TRUE(m.emissionTexture.transform.isIdentity());
}

TEST_F(GltfImport, SamplerWrapModesReachTheTextureRefs) {
  GltfBuilder b = withMaterial(json::object());
  const int repeat = addImageTexture(b, test::png(1, 1, {1, 2, 3}));
  const int clampMirror = addImageTexture(b, test::png(1, 1, {1, 2, 3}));
  b.append("samplers", {{"wrapS", 33071}, {"wrapT", 33648}});
  b.doc["textures"][clampMirror]["sampler"] = 0;
  b.doc["materials"][0] = {{"pbrMetallicRoughness", {{"baseColorTexture", {{"index", repeat}}}}},
                           {"emissiveTexture", {{"index", clampMirror}}}};
  import(b);
  const Material& m = onlyMaterialOfMesh();
  EXPECT_EQ(m.diffuseTexture.wrapS, WrapMode::kRepeat);  // no sampler: glTF's default
  EXPECT_EQ(m.diffuseTexture.wrapT, WrapMode::kRepeat);
  EXPECT_EQ(m.emissionTexture.wrapS, WrapMode::kClampToEdge);
  EXPECT_EQ(m.emissionTexture.wrapT, WrapMode::kMirroredRepeat);
  EXPECT_EQ(m.diffuseTexture.magFilter, MagFilter::kLinear);  // undefined: linear, trilinear
  EXPECT_EQ(m.diffuseTexture.minFilter, MinFilter::kLinearMipmapLinear);
  EXPECT_EQ(m.emissionTexture.magFilter, MagFilter::kLinear);
  auto emissionRefOf = [&](const GltfBuilder& file) {
    scene_ = Scene();
    import(file);
    return onlyMaterialOfMesh().emissionTexture;
  };
  b.doc["samplers"][0]["magFilter"] = 9728;
  b.doc["samplers"][0]["minFilter"] = 9984;
  EXPECT_EQ(emissionRefOf(b).magFilter, MagFilter::kNearest);
  EXPECT_EQ(emissionRefOf(b).minFilter, MinFilter::kNearestMipmapNearest);
  b.doc["samplers"][0]["minFilter"] = 9729;
  EXPECT_EQ(emissionRefOf(b).minFilter, MinFilter::kLinear);

  // Wrong values name their JSON location.
  auto expectError = [&](const std::string& jsonPath, const std::string& text) {
    try {
      import(b);
      ADD_FAILURE() << "no InputError";
    } catch (const InputError& e) {
      EXPECT_EQ(e.location().jsonPath, jsonPath);
      EXPECT_NE(std::string(e.what()).find(text), std::string::npos) << e.what();
    }
  };
  b.doc["samplers"][0]["wrapT"] = 10241;  // a filter constant, not a wrap mode
  expectError("/samplers/0/wrapT", "wrap mode 10241");
  b.doc["samplers"][0]["wrapT"] = 10497;
  b.doc["samplers"][0]["magFilter"] = 9984;  // a mipmap filter cannot magnify
  expectError("/samplers/0/magFilter", "magFilter 9984");
  b.doc["samplers"][0]["magFilter"] = 9729;
  b.doc["samplers"][0]["minFilter"] = 33071;
  expectError("/samplers/0/minFilter", "minFilter 33071");
  b.doc["samplers"][0]["minFilter"] = 9987;
  b.doc["textures"][clampMirror]["sampler"] = 3;
  expectError("/textures/1/sampler", "refers to sampler 3");
}

TEST_F(GltfImport, ExternalSixteenBitImageAndUnsupportedTexCoord) {
  const std::vector<uint8_t> image = test::png(1, 1, {65535, 256, 1}, 16);
  test::writeBytes(dir_ / "my wall.png", image.data(), image.size());
  GltfBuilder b = withMaterial(json::object());
  b.append("images", {{"uri", "my%20wall.png"}});
  b.append("textures", {{"source", 0}});
  b.doc["materials"][0] = {{"pbrMetallicRoughness", {{"baseColorTexture", {{"index", 0}, {"texCoord", 2}}}}}};
  const GltfImportResult r = import(b, {{}, "x/"});
  const Material& m = onlyMaterialOfMesh();
  const Texture& t = scene_.texture(m.diffuseTexture.texture);
  EXPECT_EQ(t.name, "x/my wall");
  EXPECT_EQ(t.sourcePath, (dir_ / "my wall.png").string());
  EXPECT_EQ(t.bitsPerChannel, 16);
  ASSERT_EQ(t.pixels.size(), 8u);
  uint16_t px[4];
  std::memcpy(px, t.pixels.data(), 8);
  EXPECT_EQ(px[0], 65535);
  EXPECT_EQ(px[1], 256);
  EXPECT_EQ(px[2], 1);
  EXPECT_EQ(px[3], 65535);
  EXPECT_EQ(m.diffuseTexture.texCoord, 0);
  EXPECT_TRUE(contains(r.warnings, "uses TEXCOORD_2, which fly does not import"));
}

// --- Lights and cameras.

TEST_F(GltfImport, PunctualLights) {
  GltfBuilder b;
  b.useExtension("KHR_lights_punctual");
  b.doc["extensions"]["KHR_lights_punctual"]["lights"] = {
      {{"name", "bulb"}, {"type", "point"}, {"color", {1, 0.5, 0.25}}, {"intensity", 100}},
      {{"type", "spot"},
       {"intensity", 50},
       {"range", 10},
       {"spot", {{"innerConeAngle", 0.2}, {"outerConeAngle", 0.6}}}},
      {{"name", "sun"}, {"type", "directional"}, {"intensity", 1000}}};
  for (int i = 0; i < 3; ++i) b.node({{"extensions", {{"KHR_lights_punctual", {{"light", i}}}}}});
  b.node({{"extensions", {{"KHR_lights_punctual", {{"light", 0}}}}}});
  b.scene({0, 1, 2, 3});
  const GltfImportResult r = import(b);
  ASSERT_EQ(scene_.lights().size(), 3u);
  const Light& bulb = scene_.light(scene_.node(r.roots[0]).light);
  EXPECT_EQ(bulb.name, "bulb");
  EXPECT_EQ(bulb.type, LightType::kPoint);
  expectRgb(bulb.color, {1, 0.5f, 0.25f});
  EXPECT_FLOAT_EQ(bulb.intensity, 100.0f);
  EXPECT_EQ(bulb.rangeM, kInf);
  const Light& spot = scene_.light(scene_.node(r.roots[1]).light);
  EXPECT_EQ(spot.name, "light1");
  EXPECT_EQ(spot.type, LightType::kSpot);
  EXPECT_FLOAT_EQ(spot.rangeM, 10.0f);
  EXPECT_FLOAT_EQ(spot.innerConeRad, 0.2f);
  EXPECT_FLOAT_EQ(spot.outerConeRad, 0.6f);
  const Light& sun = scene_.light(scene_.node(r.roots[2]).light);
  EXPECT_EQ(sun.type, LightType::kDirectional);
  EXPECT_FLOAT_EQ(sun.intensity, 1000.0f);                                  // lux
  EXPECT_EQ(scene_.node(r.roots[3]).light, scene_.node(r.roots[0]).light);  // shared
}

TEST_F(GltfImport, SpotConeOutsideTheSpecIsAnInputError) {
  GltfBuilder b;
  b.doc["extensions"]["KHR_lights_punctual"]["lights"] = {
      {{"type", "spot"}, {"spot", {{"innerConeAngle", 0.8}, {"outerConeAngle", 0.6}}}}};
  b.node({{"extensions", {{"KHR_lights_punctual", {{"light", 0}}}}}});
  b.scene({0});
  EXPECT_NE(importError(b).find("light 0: spot cone angles must satisfy"), std::string::npos);
}

TEST_F(GltfImport, PerspectiveAndOrthographicCameras) {
  GltfBuilder b;
  b.append("cameras", {{"name", "eye"},
                       {"type", "perspective"},
                       {"perspective", {{"yfov", 0.9}, {"aspectRatio", 1.5}, {"znear", 0.1}}}});
  b.append("cameras",
           {{"type", "perspective"}, {"perspective", {{"yfov", 0.5}, {"znear", 1}, {"zfar", 100}}}});
  b.append("cameras", {{"type", "orthographic"},
                       {"orthographic", {{"xmag", 2}, {"ymag", 1}, {"znear", 0.5}, {"zfar", 50}}}});
  for (int i = 0; i < 3; ++i) b.node({{"camera", i}, {"translation", {0, 1.7, 5}}});
  b.scene({0, 1, 2});
  const GltfImportResult r = import(b);
  const Camera& eye = scene_.camera(scene_.node(r.roots[0]).camera);
  EXPECT_EQ(eye.name, "eye");
  EXPECT_EQ(eye.projection, Projection::kPerspective);
  EXPECT_FLOAT_EQ(eye.yfovRad, 0.9f);
  EXPECT_FLOAT_EQ(eye.aspectRatio, 1.5f);
  EXPECT_FLOAT_EQ(eye.znearM, 0.1f);
  EXPECT_EQ(eye.zfarM, kInf);  // no zfar: infinite projection
  const Camera& far = scene_.camera(scene_.node(r.roots[1]).camera);
  EXPECT_EQ(far.name, "camera1");
  EXPECT_EQ(far.aspectRatio, 0.0f);  // take the output image's
  EXPECT_FLOAT_EQ(far.zfarM, 100.0f);
  const Camera& ortho = scene_.camera(scene_.node(r.roots[2]).camera);
  EXPECT_EQ(ortho.projection, Projection::kOrthographic);
  EXPECT_FLOAT_EQ(ortho.xmagM, 2.0f);
  EXPECT_FLOAT_EQ(ortho.ymagM, 1.0f);
  EXPECT_FLOAT_EQ(ortho.znearM, 0.5f);
  EXPECT_FLOAT_EQ(ortho.zfarM, 50.0f);
  expectVec(vec3(scene_.worldFromLocal(r.roots[2])[3]), {0, 1.7f, 5});
}

// --- Extensions.

TEST_F(GltfImport, ExtensionsRequiredMustBeSupportedAndUsedOnesOnlyWarn) {
  GltfBuilder b = withMaterial(json::object());
  b.useExtension("KHR_materials_iridescence");
  b.useExtension("KHR_lights_punctual", true);
  const GltfImportResult r = import(b);
  EXPECT_TRUE(contains(r.warnings,
                       "the glTF extension 'KHR_materials_iridescence' is not supported: the "
                       "thin-film iridescence is ignored"));

  b.useExtension("EXT_mesh_gpu_instancing", true);
  const std::string error = importError(b);
  EXPECT_NE(error.find("requires the glTF extension 'EXT_mesh_gpu_instancing', which fly does not support"),
            std::string::npos);
  EXPECT_NE(error.find("instancing resolved into ordinary nodes"), std::string::npos) << error;
}

// --- Bad input.

// Every case of tests/data/bad/gltf.expect (which `fly info` is also run on): code 3 = InputError whose
// message contains the text, code 0 = imported with a warning that contains it.
TEST_F(GltfImport, BadInputCorpus) {
  const std::filesystem::path bad = std::filesystem::path(FLY_TEST_DATA_DIR) / "bad";
  std::ifstream expect(bad / "gltf.expect");
  ASSERT_TRUE(expect) << "cannot open gltf.expect";
  int cases = 0;
  for (std::string line; std::getline(expect, line);) {
    if (line.empty()) continue;
    std::istringstream fields(line);
    std::string path, code, text;
    std::getline(fields, path, '\t');
    std::getline(fields, code, '\t');
    std::getline(fields, text);
    SCOPED_TRACE(path);
    Scene s;
    if (code == "3") {
      try {
        importGltf(s, bad / path);
        ADD_FAILURE() << "no InputError";
      } catch (const InputError& e) {
        EXPECT_NE(std::string(e.what()).find(text), std::string::npos) << e.what();
        EXPECT_FALSE(e.hint().empty()) << e.what();
        EXPECT_NE(e.location().file.find(std::filesystem::path(path).filename().string()), std::string::npos);
      }
      EXPECT_TRUE(s.nodes().empty() && s.meshes().empty() && s.materials().empty());
    } else {
      ASSERT_EQ(code, "0");
      const GltfImportResult r = importGltf(s, bad / path);
      EXPECT_TRUE(contains(r.warnings, text)) << (r.warnings.empty() ? "no warnings" : r.warnings[0]);
      EXPECT_TRUE(contains(logged_, text));
    }
    ++cases;
  }
  EXPECT_GE(cases, 10);
}

TEST_F(GltfImport, ErrorsCarryTheJsonLocation) {
  const std::filesystem::path bad = std::filesystem::path(FLY_TEST_DATA_DIR) / "bad/gltf";
  Scene s;
  try {
    importGltf(s, bad / "accessor-out-of-range.gltf");
    FAIL();
  } catch (const InputError& e) {
    EXPECT_EQ(e.location().file, (bad / "accessor-out-of-range.gltf").string());
    EXPECT_EQ(e.location().jsonPath, "/accessors/0");
  }
  try {
    importGltf(s, bad / "invalid-json.gltf");
    FAIL();
  } catch (const InputError& e) {
    EXPECT_EQ(e.location().line, 4);
    EXPECT_GT(e.location().column, 0);
  }
}

TEST_F(GltfImport, MissingFilesAreReportedWithTheirElement) {
  GltfBuilder b;
  b.triangles(kTriangle, {}, "T");
  b.node({{"mesh", 0}});
  b.scene({0});
  b.writeGltfWithBin(dir_ / "m.gltf");
  std::filesystem::remove(dir_ / "m.bin");
  Scene s;
  try {
    importGltf(s, dir_ / "m.gltf");
    FAIL();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("buffer 0 refers to 'm.bin', which does not exist"),
              std::string::npos);
    EXPECT_EQ(e.location().jsonPath, "/buffers/0/uri");
  }
  // A .bin of the wrong size.
  b.writeGltfWithBin(dir_ / "m.gltf");
  test::writeText(dir_ / "m.bin", "short");
  try {
    importGltf(s, dir_ / "m.gltf");
    FAIL();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("has 5 bytes but the glTF file says 36 (byteLength)"),
              std::string::npos)
        << e.what();
  }
}

TEST_F(GltfImport, UndecodableImageIsAnInputError) {
  GltfBuilder b = withMaterial(json::object());
  std::vector<uint8_t> broken = test::png(2, 2, std::vector<uint16_t>(12, 7));
  broken.resize(40);  // the signature and part of the header survive
  const int tex = addImageTexture(b, broken);
  const int bmp = addImageTexture(b, {'B', 'M', 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0});
  b.doc["materials"][0] = {{"pbrMetallicRoughness", {{"baseColorTexture", {{"index", tex}}}}}};
  EXPECT_NE(importError(b).find(
                "image 0 'checker' (material 0 baseColorTexture): its embedded data cannot be decoded"),
            std::string::npos);
  b.doc["materials"][0] = {{"pbrMetallicRoughness", {{"baseColorTexture", {{"index", bmp}}}}}};
  EXPECT_NE(
      importError(b).find(
          "image 1 'checker' (material 0 baseColorTexture): its embedded data is not an image format fly "
          "knows; without an image decoder installed fly reads PNG and JPEG"),
      std::string::npos);
}

TEST_F(GltfImport, TextureWithoutAnImageFlyCanReadIsSkippedWithAWarning) {
  GltfBuilder b =
      withMaterial({{"name", "Web"}, {"pbrMetallicRoughness", {{"baseColorTexture", {{"index", 0}}}}}});
  b.append("textures", {{"extensions", {{"EXT_texture_webp", {{"source", 0}}}}}});
  b.useExtension("EXT_texture_webp");
  const GltfImportResult r = import(b);
  EXPECT_FALSE(onlyMaterialOfMesh().diffuseTexture);
  EXPECT_TRUE(contains(r.warnings, "texture 0 has no image fly can read"));
}

TEST_F(GltfImport, OutOfRangeReferencesAreInputErrors) {
  {
    // An embedded image whose buffer view runs past the buffer: tinygltf does not check it, the importer
    // does.
    GltfBuilder b = withMaterial({{"pbrMetallicRoughness", {{"baseColorTexture", {{"index", 0}}}}}});
    const std::vector<uint8_t> image = test::png(1, 1, {1, 2, 3});
    const int view = b.view(image);
    b.doc["bufferViews"][size_t(view)]["byteLength"] = 100000;
    b.append("images", {{"bufferView", view}, {"mimeType", "image/png"}});
    b.append("textures", {{"source", 0}});
    EXPECT_NE(importError(b).find("buffer view 1 covers bytes"), std::string::npos);
  }
  {
    GltfBuilder b;
    b.node({{"mesh", 3}});
    b.scene({0});
    EXPECT_NE(importError(b).find("node 0 refers to mesh 3, but the file has 0 meshes"), std::string::npos);
  }
  {
    GltfBuilder b;
    b.triangles(kTriangle, {}, "T", 2);
    b.node({{"mesh", 0}});
    b.scene({0});
    EXPECT_NE(importError(b).find("mesh 'T' primitive 0 refers to material 2"), std::string::npos);
  }
  {
    GltfBuilder b;
    b.node({{"children", {1}}});
    b.node(json::object());
    b.node({{"children", {1}}});
    b.scene({0, 2});
    EXPECT_NE(importError(b).find("node 1 is a child of more than one node"), std::string::npos);
  }
  {
    GltfBuilder b;
    b.triangles(kTriangle, {}, "T");
    b.doc["accessors"][0]["type"] = "VEC2";
    b.node({{"mesh", 0}});
    b.scene({0});
    EXPECT_NE(
        importError(b).find("accessor 0 (POSITION of mesh 'T' primitive 0) has type VEC2; it must be VEC3"),
        std::string::npos);
  }
  {
    GltfBuilder b = withMaterial({{"pbrMetallicRoughness", {{"roughnessFactor", 1.5}}}});
    EXPECT_NE(importError(b).find("material 0 roughnessFactor is 1.5; glTF requires a value in [0, 1]"),
              std::string::npos);
  }
}

TEST_F(GltfImport, FailedImportLeavesTheSceneUntouched) {
  GltfBuilder b = withMaterial({{"pbrMetallicRoughness", {{"baseColorTexture", {{"index", 0}}}}}});
  b.append("images", {{"uri", "gone.png"}});
  b.append("textures", {{"source", 0}});
  b.triangles(kTriangle, {}, "Fine");  // converted before the failing mesh
  b.doc["nodes"] = json::array({{{"mesh", 1}}, {{"mesh", 0}}});
  b.scene({0, 1});
  scene_.addNode(Node{});
  EXPECT_NE(
      importError(b).find("image 0 (material 0 baseColorTexture) refers to 'gone.png', which does not exist"),
      std::string::npos);
  EXPECT_EQ(scene_.nodes().size(), 1u);
  EXPECT_TRUE(scene_.meshes().empty());
  EXPECT_TRUE(scene_.materials().empty());
}

// Every prefix of a valid .glb and .gltf is an InputError, never a crash or a hang.
TEST_F(GltfImport, EveryTruncationIsAnInputError) {
  GltfBuilder b = withMaterial({{"name", "M"}});
  const std::vector<uint8_t> glb = b.glb();
  b.writeGltf(dir_ / "full.gltf");
  std::ifstream in(dir_ / "full.gltf", std::ios::binary);
  const std::string gltf((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  for (size_t n = 0; n < glb.size(); ++n) {
    test::writeBytes(dir_ / "cut.glb", glb.data(), n);
    Scene s;
    EXPECT_THROW(importGltf(s, dir_ / "cut.glb"), InputError) << n << " bytes";
  }
  for (size_t n = 0; n + 1 < gltf.size(); ++n) {  // the last byte is a newline
    test::writeBytes(dir_ / "cut.gltf", gltf.data(), n);
    Scene s;
    EXPECT_THROW(importGltf(s, dir_ / "cut.gltf"), InputError) << n << " bytes";
  }
}

}  // namespace
}  // namespace fly::sdb
