// The glTF importer tests' fixture and helpers, shared by the test files of tests/sdb that import glTF.
#pragma once

#include <gtest/gtest.h>

#include <filesystem>
#include <string>
#include <vector>

#include "base/error.h"
#include "base/log.h"
#include "gltf_builder.h"
#include "sdb/gltf_import.h"

namespace fly::sdb {

// Records what the importer logs, and keeps the test output quiet.
class GltfImport : public ::testing::Test {
 protected:
  void SetUp() override {
    previous_ = log::setSink([this](log::Level level, std::string_view m) {
      if (level == log::Level::kWarning) logged_.emplace_back(m);
    });
  }
  void TearDown() override { log::setSink(previous_); }

  GltfImportResult import(const test::GltfBuilder& b, const GltfImportOptions& options = {}) {
    const std::filesystem::path file = dir_ / "model.gltf";
    b.writeGltf(file);
    return importGltf(scene_, file, options);
  }

  // The InputError that importing `b` throws ("" when none is thrown).
  std::string importError(const test::GltfBuilder& b) {
    try {
      import(b);
    } catch (const InputError& e) {
      return e.what();
    }
    return "";
  }

  const Mesh& onlyMesh() const {
    EXPECT_EQ(scene_.meshes().size(), 1u);
    return scene_.meshes().begin()->second;
  }
  const Material& onlyMaterialOfMesh() const { return scene_.material(onlyMesh().material); }

  static bool contains(const std::vector<std::string>& texts, const std::string& part) {
    for (const std::string& t : texts) {
      if (t.find(part) != std::string::npos) return true;
    }
    return false;
  }

  test::TempDir dir_;
  Scene scene_;
  std::vector<std::string> logged_;
  log::Sink previous_;
};

inline void expectVec(const vec3& a, const vec3& b, float tol = 1e-5f) {
  EXPECT_NEAR(a.x, b.x, tol);
  EXPECT_NEAR(a.y, b.y, tol);
  EXPECT_NEAR(a.z, b.z, tol);
}

inline vec3 transformPoint(const mat4& m, const vec3& p) {
  return vec3(m * vec4(p, 1.0f));
}

inline const std::vector<float> kTriangle = {0, 0, 0, 1, 0, 0, 0, 1, 0};

// A one-triangle file whose primitive uses material 0 = `material`.
inline test::GltfBuilder withMaterial(const nlohmann::json& material) {
  test::GltfBuilder b;
  b.material(material);
  b.triangles(kTriangle, {}, "T", 0);
  b.node({{"mesh", 0}});
  b.scene({0});
  return b;
}

inline void expectRgb(const Rgb& a, const Rgb& b, float tol = 1e-6f) {
  EXPECT_NEAR(a.r, b.r, tol);
  EXPECT_NEAR(a.g, b.g, tol);
  EXPECT_NEAR(a.b, b.b, tol);
}

// Adds an embedded PNG image, a texture using it, and returns the texture's index.
inline int addImageTexture(test::GltfBuilder& b, const std::vector<uint8_t>& image) {
  const int view = b.view(image);
  b.append("images", {{"bufferView", view}, {"mimeType", "image/png"}, {"name", "checker"}});
  return b.append("textures", {{"source", int(b.doc["images"].size() - 1)}});
}

}  // namespace fly::sdb
