// Compressed glTF meshes (KHR_draco_mesh_compression, EXT_meshopt_compression): files are written here with
// Draco's and meshoptimizer's encoders, and their decoded geometry must equal the uncompressed file's.
#include <gtest/gtest.h>

#include <draco/compression/encode.h>
#include <draco/mesh/triangle_soup_mesh_builder.h>
#include <meshoptimizer.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>

#include "gltf_import_fixture.h"

namespace fly::sdb {
namespace {

using json = nlohmann::json;
using test::GltfBuilder;

constexpr int kFloat = 5126, kByte = 5120, kUInt = 5125;

// A curved 5 × 4 grid of quads: positions on a cylinder, its outward normals, and UVs.
struct Grid {
  std::vector<float> positions, normals, uvs;
  std::vector<uint32_t> indices;
  size_t vertices() const { return positions.size() / 3; }
};

Grid grid() {
  Grid g;
  const int nx = 5, ny = 4;
  for (int y = 0; y <= ny; ++y) {
    for (int x = 0; x <= nx; ++x) {
      const float a = 0.3f * float(x);
      g.positions.insert(g.positions.end(), {std::sin(a), 0.25f * float(y), std::cos(a)});
      g.normals.insert(g.normals.end(), {std::sin(a), 0.0f, std::cos(a)});
      g.uvs.insert(g.uvs.end(), {float(x) / nx, float(y) / ny});
    }
  }
  for (int y = 0; y < ny; ++y) {
    for (int x = 0; x < nx; ++x) {
      const auto v = uint32_t(y * (nx + 1) + x), w = uint32_t(nx + 1);
      g.indices.insert(g.indices.end(), {v, v + 1, v + w + 1, v, v + w + 1, v + w});
    }
  }
  return g;
}

// A mesh's triangles as corner tuples (position, normal, uv), each triangle rotated to start at its smallest
// corner and the list sorted: equal for the same geometry whatever the vertex order.
using Corner = std::array<float, 8>;
std::vector<std::array<Corner, 3>> canonicalTriangles(const Mesh& m) {
  std::vector<std::array<Corner, 3>> out;
  for (size_t t = 0; t < m.indices.size(); t += 3) {
    std::array<Corner, 3> tri;
    for (size_t k = 0; k < 3; ++k) {
      const uint32_t i = m.indices[t + k];
      const vec3 p = m.positions[i], n = m.normals[i];
      const vec2 uv = m.uv0.empty() ? vec2(0.0f) : m.uv0[i];
      tri[k] = {p.x, p.y, p.z, n.x, n.y, n.z, uv.x, uv.y};
    }
    std::rotate(tri.begin(), std::min_element(tri.begin(), tri.end()), tri.end());
    out.push_back(tri);
  }
  std::sort(out.begin(), out.end());
  return out;
}

void expectSameTriangles(const Mesh& a, const Mesh& b, float tolerance) {
  const auto ta = canonicalTriangles(a), tb = canonicalTriangles(b);
  ASSERT_EQ(ta.size(), tb.size());
  for (size_t t = 0; t < ta.size(); ++t) {
    for (size_t k = 0; k < 3; ++k) {
      for (size_t c = 0; c < 8; ++c) ASSERT_NEAR(ta[t][k][c], tb[t][k][c], tolerance) << "triangle " << t;
    }
  }
}

GltfBuilder uncompressed(const Grid& g) {
  GltfBuilder b;
  const json p = {{"attributes",
                   {{"POSITION", b.floats(g.positions, "VEC3")},
                    {"NORMAL", b.floats(g.normals, "VEC3")},
                    {"TEXCOORD_0", b.floats(g.uvs, "VEC2")}}},
                  {"indices", b.indices(g.indices)}};
  b.mesh(json::array({p}), "Grid");
  b.node({{"mesh", 0}});
  b.scene({0});
  return b;
}

// The grid as a Draco bit stream (no quantisation: lossless) and the attributes' Draco ids.
std::vector<uint8_t> dracoStream(const Grid& g, int* positionId, int* normalId, int* uvId) {
  draco::TriangleSoupMeshBuilder builder;
  const int faces = int(g.indices.size() / 3);
  builder.Start(faces);
  const int pos = builder.AddAttribute(draco::GeometryAttribute::POSITION, 3, draco::DT_FLOAT32);
  const int nor = builder.AddAttribute(draco::GeometryAttribute::NORMAL, 3, draco::DT_FLOAT32);
  const int tex = builder.AddAttribute(draco::GeometryAttribute::TEX_COORD, 2, draco::DT_FLOAT32);
  for (int f = 0; f < faces; ++f) {
    const uint32_t* v = &g.indices[size_t(3 * f)];
    builder.SetAttributeValuesForFace(pos, draco::FaceIndex(f), &g.positions[3 * v[0]],
                                      &g.positions[3 * v[1]], &g.positions[3 * v[2]]);
    builder.SetAttributeValuesForFace(nor, draco::FaceIndex(f), &g.normals[3 * v[0]], &g.normals[3 * v[1]],
                                      &g.normals[3 * v[2]]);
    builder.SetAttributeValuesForFace(tex, draco::FaceIndex(f), &g.uvs[2 * v[0]], &g.uvs[2 * v[1]],
                                      &g.uvs[2 * v[2]]);
  }
  std::unique_ptr<draco::Mesh> mesh = builder.Finalize();
  EXPECT_NE(mesh, nullptr);
  *positionId = int(mesh->attribute(pos)->unique_id());
  *normalId = int(mesh->attribute(nor)->unique_id());
  *uvId = int(mesh->attribute(tex)->unique_id());
  draco::Encoder encoder;
  draco::EncoderBuffer buffer;
  const draco::Status status = encoder.EncodeMeshToBuffer(*mesh, &buffer);
  EXPECT_TRUE(status.ok()) << status.error_msg_string();
  return std::vector<uint8_t>(buffer.data(), buffer.data() + buffer.size());
}

GltfBuilder dracoFile(const std::vector<uint8_t>& stream, size_t points, size_t indexCount, int positionId,
                      int normalId, int uvId) {
  GltfBuilder b;
  const int view = b.view(stream);
  const json p = {
      {"attributes",
       {{"POSITION", b.accessor(-1, kFloat, points, "VEC3")},
        {"NORMAL", b.accessor(-1, kFloat, points, "VEC3")},
        {"TEXCOORD_0", b.accessor(-1, kFloat, points, "VEC2")}}},
      {"indices", b.accessor(-1, kUInt, indexCount, "SCALAR")},
      {"extensions",
       {{"KHR_draco_mesh_compression",
         {{"bufferView", view},
          {"attributes", {{"POSITION", positionId}, {"NORMAL", normalId}, {"TEXCOORD_0", uvId}}}}}}}};
  b.mesh(json::array({p}), "Grid");
  b.node({{"mesh", 0}});
  b.scene({0});
  b.useExtension("KHR_draco_mesh_compression", true);
  return b;
}

TEST_F(GltfImport, DracoCompressedMeshDecodesToTheUncompressedGeometry) {
  const Grid g = grid();
  import(uncompressed(g));
  const Mesh reference = onlyMesh();
  scene_ = Scene();

  int pos = 0, nor = 0, uv = 0;
  const std::vector<uint8_t> stream = dracoStream(g, &pos, &nor, &uv);
  // Draco keeps one point per distinct corner: the 30 grid vertices.
  const GltfBuilder b = dracoFile(stream, g.vertices(), g.indices.size(), pos, nor, uv);
  b.writeGlb(dir_ / "draco.glb");
  importGltf(scene_, dir_ / "draco.glb");
  const Mesh& decoded = onlyMesh();
  EXPECT_EQ(decoded.indices.size(), g.indices.size());
  expectSameTriangles(reference, decoded, 0.0f);
}

TEST_F(GltfImport, DamagedOrMismatchedDracoStreamsAreInputErrors) {
  const Grid g = grid();
  int pos = 0, nor = 0, uv = 0;
  std::vector<uint8_t> stream = dracoStream(g, &pos, &nor, &uv);
  // The POSITION accessor declares another point count than the stream has.
  EXPECT_NE(importError(dracoFile(stream, g.vertices() + 1, g.indices.size(), pos, nor, uv))
                .find("the Draco stream has 30 points but the POSITION accessor declares 31"),
            std::string::npos);
  // An attribute id the stream does not have.
  EXPECT_NE(importError(dracoFile(stream, g.vertices(), g.indices.size(), pos, nor, 77))
                .find("Draco attribute 77 is not in the compressed mesh"),
            std::string::npos);
  // A cut-off stream.
  stream.resize(stream.size() / 2);
  const std::string error = importError(dracoFile(stream, g.vertices(), g.indices.size(), pos, nor, uv));
  EXPECT_NE(error.find("mesh 'Grid' primitive 0: the Draco-compressed mesh cannot be decoded"),
            std::string::npos)
      << error;
  EXPECT_NE(error.find("/meshes/0/primitives/0/extensions/KHR_draco_mesh_compression"), std::string::npos);
}

// EXT_meshopt_compression: positions (ATTRIBUTES), normals as 8-bit octahedral vectors (ATTRIBUTES +
// OCTAHEDRAL filter) and the triangles (TRIANGLES) in buffer 0; buffer 1 is the extension's data-less
// fallback.
GltfBuilder meshoptFile(const Grid& g) {
  GltfBuilder b;
  const size_t n = g.vertices();
  auto compressedView = [&](const std::vector<uint8_t>& encoded, size_t count, size_t stride,
                            const char* mode, const char* filter, size_t fallbackOffset) {
    while (b.bin.size() % 4) b.bin.push_back(0);
    const size_t offset = b.bin.size();
    b.bin.resize(offset + encoded.size());
    std::memcpy(b.bin.data() + offset, encoded.data(), encoded.size());
    json ext = {{"buffer", 0},          {"byteOffset", offset}, {"byteLength", encoded.size()},
                {"byteStride", stride}, {"count", count},       {"mode", mode}};
    if (filter) ext["filter"] = filter;
    json v = {{"buffer", 1},
              {"byteOffset", fallbackOffset},
              {"byteLength", count * stride},
              {"extensions", {{"EXT_meshopt_compression", ext}}}};
    if (std::string(mode) == "ATTRIBUTES") v["byteStride"] = stride;
    return b.append("bufferViews", v);
  };
  std::vector<uint8_t> encoded(meshopt_encodeVertexBufferBound(n, 12));
  encoded.resize(meshopt_encodeVertexBuffer(encoded.data(), encoded.size(), g.positions.data(), n, 12));
  const int positions = compressedView(encoded, n, 12, "ATTRIBUTES", nullptr, 0);

  std::vector<float> normals4;  // meshopt_encodeFilterOct reads 4 floats per vector
  for (size_t i = 0; i < n; ++i)
    normals4.insert(normals4.end(), {g.normals[3 * i], g.normals[3 * i + 1], g.normals[3 * i + 2], 0.0f});
  std::vector<int8_t> oct(4 * n);
  meshopt_encodeFilterOct(oct.data(), n, 4, 8, normals4.data());
  encoded.assign(meshopt_encodeVertexBufferBound(n, 4), 0);
  encoded.resize(meshopt_encodeVertexBuffer(encoded.data(), encoded.size(), oct.data(), n, 4));
  const int normals = compressedView(encoded, n, 4, "ATTRIBUTES", "OCTAHEDRAL", 12 * n);

  encoded.assign(meshopt_encodeIndexBufferBound(g.indices.size(), n), 0);
  encoded.resize(
      meshopt_encodeIndexBuffer(encoded.data(), encoded.size(), g.indices.data(), g.indices.size()));
  const int indices = compressedView(encoded, g.indices.size(), 4, "TRIANGLES", nullptr, 16 * n);

  const json p = {{"attributes",
                   {{"POSITION", b.accessor(positions, kFloat, n, "VEC3")},
                    {"NORMAL", b.accessor(normals, kByte, n, "VEC3", true)}}},
                  {"indices", b.accessor(indices, kUInt, g.indices.size(), "SCALAR")}};
  b.mesh(json::array({p}), "Grid");
  b.node({{"mesh", 0}});
  b.scene({0});
  b.moreBuffers.push_back({{"byteLength", 16 * n + 4 * g.indices.size()},
                           {"extensions", {{"EXT_meshopt_compression", {{"fallback", true}}}}}});
  b.useExtension("EXT_meshopt_compression", true);
  b.useExtension("KHR_mesh_quantization", true);
  return b;
}

TEST_F(GltfImport, MeshoptCompressedMeshDecodesToTheUncompressedGeometry) {
  Grid g = grid();
  g.uvs.clear();
  GltfBuilder plain;
  const json p = {
      {"attributes",
       {{"POSITION", plain.floats(g.positions, "VEC3")}, {"NORMAL", plain.floats(g.normals, "VEC3")}}},
      {"indices", plain.indices(g.indices)}};
  plain.mesh(json::array({p}), "Grid");
  plain.node({{"mesh", 0}});
  plain.scene({0});
  import(plain);
  const Mesh reference = onlyMesh();

  const GltfBuilder b = meshoptFile(g);
  for (const char* name : {"meshopt.gltf", "meshopt.glb"}) {
    scene_ = Scene();
    if (std::string(name).ends_with(".glb")) {
      b.writeGlb(dir_ / name);
    } else {
      b.writeGltf(dir_ / name);
    }
    importGltf(scene_, dir_ / name);
    const Mesh& decoded = onlyMesh();
    // Positions are lossless and the vertex order is kept (the index codec may rotate a triangle's corners);
    // 8-bit octahedral normals are within 2/127 per component after the importer renormalises them.
    EXPECT_EQ(decoded.positions, reference.positions) << name;
    for (size_t i = 0; i < reference.normals.size(); ++i) {
      expectVec(decoded.normals[i], reference.normals[i], 2.0f / 127.0f);
    }
    expectSameTriangles(reference, decoded, 2.0f / 127.0f);
  }
}

TEST_F(GltfImport, DamagedMeshoptDataIsAnInputError) {
  GltfBuilder b = meshoptFile(grid());
  b.bin.resize(b.bin.size() - 40);  // cuts into the index stream's range
  std::string error = importError(b);
  EXPECT_NE(error.find("buffer view 2 (EXT_meshopt_compression) reads bytes"), std::string::npos) << error;
  b = meshoptFile(grid());
  b.bin[0] ^= 0x5a;  // the positions' header byte (0xA0 | version): an unknown version
  error = importError(b);
  EXPECT_NE(error.find("(EXT_meshopt_compression) cannot be decoded"), std::string::npos) << error;
  b = meshoptFile(grid());
  b.doc["bufferViews"][0]["extensions"]["EXT_meshopt_compression"]["mode"] = "LINES";
  EXPECT_NE(importError(b).find("has mode 'LINES'; the extension defines ATTRIBUTES, TRIANGLES and INDICES"),
            std::string::npos);
}

}  // namespace
}  // namespace fly::sdb
