// Building a TraceRdb by hand, for tests and benchmarks: indexed grids of triangles, uniform skies, punctual
// lights. World space is glTF's (+Y up, metres).
#pragma once

#include <cstdint>
#include <utility>
#include <vector>

#include "base/color.h"
#include "base/math.h"
#include "rdb/trace_rdb.h"

namespace fly::rdb {

// One TraceMesh per grid.
struct TraceRdbBuilder {
  TraceRdb rdb;

  uint32_t material(const Rgb& diffuse, const Rgb& emissionCdM2 = Rgb(0.0f)) {
    TraceMaterial m;
    m.diffuse = diffuse;
    m.diffuseColor = diffuse;  // no reflection or transmission: the energy rule leaves it as it is
    m.emissionCdM2 = emissionCdM2;
    rdb.materials.push_back(m);
    return static_cast<uint32_t>(rdb.materials.size() - 1);
  }
  // A texture of width × height texels and `channels` channels (TraceTexture's layout); returns its index.
  uint32_t texture(uint32_t width, uint32_t height, uint32_t channels, std::vector<uint8_t> texels) {
    rdb.textures.push_back({width, height, channels, std::move(texels)});
    return static_cast<uint32_t>(rdb.textures.size() - 1);
  }
  // (n + 1)² shared vertices from origin along edgeU and edgeV, facing cross(edgeU, edgeV), with texture
  // coordinates uv0 = uvScale · (fraction along edgeU, fraction along edgeV).
  void grid(const vec3& origin, const vec3& edgeU, const vec3& edgeV, uint32_t n, uint32_t mat,
            bool twoSided = false, float uvScale = 1.0f) {
    TraceMesh mesh;
    mesh.firstVertex = static_cast<uint32_t>(rdb.positionsM.size());
    mesh.firstTriangle = static_cast<uint32_t>(rdb.triangleCount());
    mesh.twoSided = twoSided;
    const vec3 normal = glm::normalize(glm::cross(edgeU, edgeV));
    for (uint32_t j = 0; j <= n; ++j) {
      for (uint32_t i = 0; i <= n; ++i) {
        rdb.positionsM.push_back(origin + edgeU * (static_cast<float>(i) / static_cast<float>(n)) +
                                 edgeV * (static_cast<float>(j) / static_cast<float>(n)));
        rdb.normals.push_back(normal);
        rdb.uv0.push_back(uvScale * vec2(static_cast<float>(i), static_cast<float>(j)) /
                          static_cast<float>(n));
      }
    }
    auto at = [&](uint32_t i, uint32_t j) { return mesh.firstVertex + j * (n + 1) + i; };
    for (uint32_t j = 0; j < n; ++j) {
      for (uint32_t i = 0; i < n; ++i) {
        rdb.indices.insert(rdb.indices.end(), {at(i, j), at(i + 1, j), at(i + 1, j + 1)});
        rdb.indices.insert(rdb.indices.end(), {at(i, j), at(i + 1, j + 1), at(i, j + 1)});
        for (int k = 0; k < 2; ++k) {
          rdb.triangleMaterial.push_back(mat);
          if (maxComponent(rdb.materials[mat].emissionCdM2) > 0.0f) {
            rdb.emissiveTriangles.push_back(static_cast<uint32_t>(rdb.triangleMaterial.size() - 1));
          }
        }
      }
    }
    mesh.vertexCount = static_cast<uint32_t>(rdb.positionsM.size()) - mesh.firstVertex;
    mesh.triangleCount = static_cast<uint32_t>(rdb.triangleCount()) - mesh.firstTriangle;
    rdb.meshes.push_back(mesh);
  }
  // The same n × n quads, each with 4 vertices of its own (unwelded, as many exporters write them).
  void tiles(const vec3& origin, const vec3& edgeU, const vec3& edgeV, uint32_t n, uint32_t mat) {
    TraceMesh mesh;
    mesh.firstVertex = static_cast<uint32_t>(rdb.positionsM.size());
    mesh.firstTriangle = static_cast<uint32_t>(rdb.triangleCount());
    const vec3 normal = glm::normalize(glm::cross(edgeU, edgeV));
    const float step = 1.0f / static_cast<float>(n);
    for (uint32_t j = 0; j < n; ++j) {
      for (uint32_t i = 0; i < n; ++i) {
        const auto first = static_cast<uint32_t>(rdb.positionsM.size());
        for (auto [di, dj] : {std::pair{0u, 0u}, {1u, 0u}, {1u, 1u}, {0u, 1u}}) {
          rdb.positionsM.push_back(origin + edgeU * (static_cast<float>(i + di) * step) +
                                   edgeV * (static_cast<float>(j + dj) * step));
          rdb.normals.push_back(normal);
        }
        rdb.indices.insert(rdb.indices.end(), {first, first + 1, first + 2, first, first + 2, first + 3});
        rdb.triangleMaterial.insert(rdb.triangleMaterial.end(), {mat, mat});
      }
    }
    mesh.vertexCount = static_cast<uint32_t>(rdb.positionsM.size()) - mesh.firstVertex;
    mesh.triangleCount = static_cast<uint32_t>(rdb.triangleCount()) - mesh.firstTriangle;
    rdb.meshes.push_back(mesh);
  }
  // y = 0 from −half to half in x and z, facing +Y.
  void ground(float halfM, uint32_t n, uint32_t mat, bool twoSided = false) {
    grid(vec3(-halfM, 0, -halfM), vec3(0, 0, 2 * halfM), vec3(2 * halfM, 0, 0), n, mat, twoSided);
  }
  void uniformSky(const Rgb& radianceCdM2, uint32_t resolution = 16) {
    rdb.sky.resolution = resolution;
    rdb.sky.radianceCdM2.assign(size_t{resolution} * resolution, radianceCdM2);
  }
  void pointLight(const vec3& positionM, const Rgb& intensityCd) {
    TracePunctualLight light;
    light.type = PunctualType::kPoint;
    light.positionM = positionM;
    light.intensity = intensityCd;
    rdb.punctualLights.push_back(light);
  }
  // The sun: a disc of the default angular size towards `towardsSun`, normalLux on a surface facing it.
  void sun(const vec3& towardsSun, const Rgb& normalLux) {
    rdb.hasSun = true;
    rdb.sun.directionWorld = glm::normalize(towardsSun);
    rdb.sun.normalIlluminanceLux = normalLux;
  }
  void directionalLight(const vec3& towardsLight, const Rgb& lux) {
    TracePunctualLight light;
    light.type = PunctualType::kDirectional;
    light.directionWorld = -glm::normalize(towardsLight);
    light.intensity = lux;
    rdb.punctualLights.push_back(light);
  }
};

}  // namespace fly::rdb
