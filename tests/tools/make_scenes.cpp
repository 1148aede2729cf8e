// make_scenes: writes the glTF models of the sample scenes from code, so that one program regenerates them
// and a test can check that the committed files are what it writes.
//
//   make_scenes OUTDIR   writes OUTDIR/<scene>/<scene>.gltf and <scene>.bin for every scene
//
// Every model: metres, +Y up, north = −Z (the site default), counter-clockwise front faces, unit per-vertex
// normals, TEXCOORD_0 in metres along each surface (texture t = −v, so that an image stands upright on a
// wall). Surfaces are split into cells of at most a given size on one grid per surface (no T-junctions inside
// a surface), so that per-vertex light maps have vertices to store light at. The output is the same byte for
// byte on every run: JSON keys keep a fixed order and numbers are written as the shortest decimal that reads
// back to the same float. After writing, each model is read back with tinygltf and checked: indices in range,
// unit normals that agree with the winding, no degenerate triangles. The scenes are described in
// scenes/README.md.
#include <algorithm>
#include <array>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <exception>
#include <filesystem>
#include <fstream>
#include <stdexcept>
#include <string>
#include <tuple>
#include <utility>
#include <vector>

#include <tiny_gltf.h>
#include <glm/glm.hpp>
#include <glm/gtc/quaternion.hpp>
#include <nlohmann/json.hpp>

namespace {

namespace fs = std::filesystem;
using Json = nlohmann::ordered_json;
using glm::dvec2;
using glm::dvec3;

// -----------------------------------------------------------------------------------------------------------
// Geometry

// The triangles of one material in one mesh.
struct Primitive {
  std::string material;
  std::vector<glm::vec3> positions;  // metres
  std::vector<glm::vec3> normals;    // unit
  std::vector<glm::vec2> uvs;        // metres
  std::vector<std::uint32_t> indices;

  std::uint32_t vertex(dvec3 p, dvec3 n, dvec2 uv) {
    positions.emplace_back(p);
    normals.emplace_back(glm::normalize(n));
    uvs.emplace_back(uv.x, -uv.y);
    return static_cast<std::uint32_t>(positions.size() - 1);
  }
  void triangle(std::uint32_t a, std::uint32_t b, std::uint32_t c) {
    indices.insert(indices.end(), {a, b, c});
  }
};

// Coordinates from lo to hi through every break inside (lo, hi); each interval between them is split into
// equal steps of at most cellM. Surfaces that share an edge call this with the same breaks, so their vertices
// match.
std::vector<double> gridLines(double lo, double hi, std::vector<double> breaks, double cellM) {
  std::erase_if(breaks, [&](double b) { return b <= lo || b >= hi; });
  breaks.push_back(lo);
  breaks.push_back(hi);
  std::sort(breaks.begin(), breaks.end());
  breaks.erase(std::unique(breaks.begin(), breaks.end()), breaks.end());
  std::vector<double> lines;
  for (std::size_t i = 0; i + 1 < breaks.size(); ++i) {
    const double a = breaks[i], b = breaks[i + 1];
    const int n = std::max(1, static_cast<int>(std::ceil((b - a) / cellM - 1e-9)));
    for (int k = 0; k < n; ++k) lines.push_back(a + (b - a) * k / n);
  }
  lines.push_back(hi);
  return lines;
}

struct Rect {
  double u0, u1, v0, v1;
};

// A flat rectangle origin + u·uAxis + v·vAxis with u ∈ [u0, u1], v ∈ [v0, v1], less the holes, on grid lines
// through every hole edge and through uBreaks / vBreaks. Its front is uAxis × vAxis, or the other side when
// `back` is set.
struct Panel {
  dvec3 origin, uAxis, vAxis;  // the axes are orthonormal
  double u0, u1, v0, v1;
  std::vector<Rect> holes;
  std::vector<double> uBreaks, vBreaks;
  bool back = false;
};

void addPanel(Primitive& prim, const Panel& panel, double cellM) {
  std::vector<double> ub = panel.uBreaks, vb = panel.vBreaks;
  for (const Rect& h : panel.holes) {
    ub.insert(ub.end(), {h.u0, h.u1});
    vb.insert(vb.end(), {h.v0, h.v1});
  }
  const std::vector<double> us = gridLines(panel.u0, panel.u1, ub, cellM);
  const std::vector<double> vs = gridLines(panel.v0, panel.v1, vb, cellM);
  const dvec3 normal = glm::cross(panel.uAxis, panel.vAxis) * (panel.back ? -1.0 : 1.0);
  const std::size_t nu = us.size(), nv = vs.size();
  std::vector<std::int64_t> index(nu * nv, -1);
  const auto at = [&](std::size_t i, std::size_t j) {
    std::int64_t& k = index[j * nu + i];
    if (k < 0) {
      const dvec3 p = panel.origin + us[i] * panel.uAxis + vs[j] * panel.vAxis;
      k = prim.vertex(p, normal, {panel.back ? -us[i] : us[i], vs[j]});
    }
    return static_cast<std::uint32_t>(k);
  };
  for (std::size_t j = 0; j + 1 < nv; ++j) {
    for (std::size_t i = 0; i + 1 < nu; ++i) {
      const double uc = 0.5 * (us[i] + us[i + 1]), vc = 0.5 * (vs[j] + vs[j + 1]);
      const bool inHole = std::any_of(panel.holes.begin(), panel.holes.end(), [&](const Rect& h) {
        return uc > h.u0 && uc < h.u1 && vc > h.v0 && vc < h.v1;
      });
      if (inHole) continue;
      const std::uint32_t a = at(i, j), b = at(i + 1, j), c = at(i + 1, j + 1), d = at(i, j + 1);
      if (panel.back) {
        prim.triangle(a, c, b);
        prim.triangle(a, d, c);
      } else {
        prim.triangle(a, b, c);
        prim.triangle(a, c, d);
      }
    }
  }
}

// A bilinear patch through four corners, turned so that its front faces `facing`, split into cells of at most
// cellM. Normals are those of the bilinear surface, so a slightly non-planar quad (the Cornell box's measured
// walls) stays smooth.
void addPatch(Primitive& prim, std::array<dvec3, 4> c, dvec3 facing, double cellM) {
  const dvec3 n = glm::cross(c[2] - c[0], c[3] - c[1]);
  const double agree = glm::dot(glm::normalize(n), glm::normalize(facing));
  if (std::abs(agree) < 0.1) throw std::logic_error("addPatch: `facing` is nearly in the patch's plane");
  if (agree < 0) std::swap(c[1], c[3]);
  const auto [p00, p10, p11, p01] = c;
  const double lenU = std::max(glm::length(p10 - p00), glm::length(p11 - p01));
  const double lenV = std::max(glm::length(p01 - p00), glm::length(p11 - p10));
  const int nu = std::max(1, static_cast<int>(std::ceil(lenU / cellM - 1e-9)));
  const int nv = std::max(1, static_cast<int>(std::ceil(lenV / cellM - 1e-9)));
  const double meanU = 0.5 * (glm::length(p10 - p00) + glm::length(p11 - p01));
  const double meanV = 0.5 * (glm::length(p01 - p00) + glm::length(p11 - p10));
  const std::uint32_t first = static_cast<std::uint32_t>(prim.positions.size());
  for (int j = 0; j <= nv; ++j) {
    for (int i = 0; i <= nu; ++i) {
      const double s = static_cast<double>(i) / nu, t = static_cast<double>(j) / nv;
      const dvec3 p = (1 - t) * ((1 - s) * p00 + s * p10) + t * ((1 - s) * p01 + s * p11);
      const dvec3 dS = (1 - t) * (p10 - p00) + t * (p11 - p01);
      const dvec3 dT = (1 - s) * (p01 - p00) + s * (p11 - p10);
      prim.vertex(p, glm::cross(dS, dT), {s * meanU, t * meanV});
    }
  }
  const auto at = [&](int i, int j) { return first + static_cast<std::uint32_t>(j * (nu + 1) + i); };
  for (int j = 0; j < nv; ++j) {
    for (int i = 0; i < nu; ++i) {
      prim.triangle(at(i, j), at(i + 1, j), at(i + 1, j + 1));
      prim.triangle(at(i, j), at(i + 1, j + 1), at(i, j + 1));
    }
  }
}

// Triangle a, b, c (counter-clockwise seen from the front) split into n² triangles.
void addTriangle(Primitive& prim, dvec3 a, dvec3 b, dvec3 c, int n) {
  const dvec3 normal = glm::normalize(glm::cross(b - a, c - a));
  const dvec3 uAxis = glm::normalize(b - a), vAxis = glm::cross(normal, uAxis);
  std::vector<std::uint32_t> row, next;
  for (int j = 0; j <= n; ++j) {
    next.clear();
    for (int i = 0; i <= n - j; ++i) {
      const dvec3 p = a + (b - a) * (static_cast<double>(i) / n) + (c - a) * (static_cast<double>(j) / n);
      next.push_back(prim.vertex(p, normal, {glm::dot(p - a, uAxis), glm::dot(p - a, vAxis)}));
    }
    if (j > 0) {
      // `row` holds n − j + 2 vertices, `next` one fewer.
      for (std::size_t i = 0; i < next.size(); ++i) {
        prim.triangle(row[i], row[i + 1], next[i]);
        if (i + 1 < next.size()) prim.triangle(row[i + 1], next[i + 1], next[i]);
      }
    }
    std::swap(row, next);
  }
}

// The six faces of the axis-aligned box lo..hi as panels whose fronts face outwards.
enum class Face { kPosX, kNegX, kPosY, kNegY, kPosZ, kNegZ };

Panel boxFace(dvec3 lo, dvec3 hi, Face f) {
  switch (f) {
    case Face::kPosX:
      return {{hi.x, 0, 0}, {0, 0, -1}, {0, 1, 0}, -hi.z, -lo.z, lo.y, hi.y};
    case Face::kNegX:
      return {{lo.x, 0, 0}, {0, 0, 1}, {0, 1, 0}, lo.z, hi.z, lo.y, hi.y};
    case Face::kPosY:
      return {{0, hi.y, 0}, {1, 0, 0}, {0, 0, -1}, lo.x, hi.x, -hi.z, -lo.z};
    case Face::kNegY:
      return {{0, lo.y, 0}, {1, 0, 0}, {0, 0, 1}, lo.x, hi.x, lo.z, hi.z};
    case Face::kPosZ:
      return {{0, 0, hi.z}, {1, 0, 0}, {0, 1, 0}, lo.x, hi.x, lo.y, hi.y};
    case Face::kNegZ:
      return {{0, 0, lo.z}, {-1, 0, 0}, {0, 1, 0}, -hi.x, -lo.x, lo.y, hi.y};
  }
  throw std::logic_error("boxFace: bad face");
}

// A closed box, less the faces in `skip` (a face that rests on another surface is left out rather than
// doubled).
void addBox(Primitive& prim, dvec3 lo, dvec3 hi, double cellM, std::vector<Face> skip = {}) {
  for (Face f : {Face::kPosX, Face::kNegX, Face::kPosY, Face::kNegY, Face::kPosZ, Face::kNegZ}) {
    if (std::find(skip.begin(), skip.end(), f) == skip.end()) addPanel(prim, boxFace(lo, hi, f), cellM);
  }
}

// An upright prism over a convex footprint (x, z corners in either order) from y0 to y1, without its bottom.
void addPrism(Primitive& prim, const std::vector<dvec2>& footprintXZ, double y0, double y1, double cellM) {
  dvec2 centre{0.0};
  for (dvec2 p : footprintXZ) centre += p / static_cast<double>(footprintXZ.size());
  for (std::size_t i = 0; i < footprintXZ.size(); ++i) {
    const dvec2 a = footprintXZ[i], b = footprintXZ[(i + 1) % footprintXZ.size()];
    const dvec2 out = 0.5 * (a + b) - centre;
    addPatch(prim, {dvec3{a.x, y0, a.y}, dvec3{b.x, y0, b.y}, dvec3{b.x, y1, b.y}, dvec3{a.x, y1, a.y}},
             {out.x, 0, out.y}, cellM);
  }
  if (footprintXZ.size() != 4) throw std::logic_error("addPrism: the top is a quad");
  std::array<dvec3, 4> top;
  for (std::size_t i = 0; i < 4; ++i) top[i] = {footprintXZ[i].x, y1, footprintXZ[i].y};
  addPatch(prim, top, {0, 1, 0}, cellM);
}

// -----------------------------------------------------------------------------------------------------------
// Models

struct Material {
  std::string name;
  glm::vec3 baseColor{0.8f};  // linear reflectance
  float roughness = 1.0f;
  bool doubleSided = false;
  float transmission = 0.0f;      // KHR_materials_transmission when > 0
  float ior = 0.0f;               // KHR_materials_ior when > 0
  glm::vec3 emissive{0.0f};       // × emissiveStrength = luminance in cd/m²
  float emissiveStrength = 1.0f;  // KHR_materials_emissive_strength when ≠ 1
};

// The window panes' material: double-sided, fully transmissive (KHR_materials_transmission), ior 1.52.
Material clearGlass() {
  return {.name = "Glass",
          .baseColor = {1.0f, 1.0f, 1.0f},
          .roughness = 0.0f,
          .doubleSided = true,
          .transmission = 1.0f,
          .ior = 1.52f};
}

struct Mesh {
  std::string name;
  std::vector<Primitive> primitives;
};

struct Node {
  std::string name;
  int mesh = -1;
  dvec3 translation{0.0};
  glm::dquat rotation{1.0, 0.0, 0.0, 0.0};
  double scale = 1.0;
  std::vector<int> children;
};

struct Model {
  std::string name;
  std::vector<Material> materials;
  std::vector<Mesh> meshes;
  std::vector<Node> nodes;
  std::vector<int> roots;

  int addMesh(std::string meshName) {
    meshes.push_back({std::move(meshName), {}});
    return static_cast<int>(meshes.size() - 1);
  }
  // The mesh's primitive of that material, appended when it is new. The reference is valid until the next
  // addMesh() or prim() call.
  Primitive& prim(int mesh, const std::string& material) {
    const bool known = std::any_of(materials.begin(), materials.end(),
                                   [&](const Material& m) { return m.name == material; });
    if (!known) throw std::logic_error(name + ": no material " + material);
    std::vector<Primitive>& ps = meshes[static_cast<std::size_t>(mesh)].primitives;
    for (Primitive& p : ps) {
      if (p.material == material) return p;
    }
    ps.push_back({material, {}, {}, {}, {}});
    return ps.back();
  }
  int addNode(Node node, int parent = -1) {
    nodes.push_back(std::move(node));
    const int index = static_cast<int>(nodes.size() - 1);
    if (parent < 0) {
      roots.push_back(index);
    } else {
      nodes[static_cast<std::size_t>(parent)].children.push_back(index);
    }
    return index;
  }
  // A mesh of the same name under a node of that name.
  int addMeshNode(const std::string& meshName, int parent = -1) {
    return addNode({.name = meshName, .mesh = addMesh(meshName)}, parent);
  }
  int meshOf(int node) const { return nodes[static_cast<std::size_t>(node)].mesh; }
};

glm::dquat rotationYDeg(double deg) {
  return glm::angleAxis(glm::radians(deg), dvec3{0, 1, 0});
}

// 1. box-room: a closed room 4 m (x) × 2.7 m × 5 m (z), inner faces, one 1.5 × 1.2 m window in the west wall.
Model boxRoom() {
  Model m{.name = "box-room"};
  m.materials = {
      {.name = "Floor", .baseColor = {0.40f, 0.30f, 0.20f}, .roughness = 0.6f},
      {.name = "Wall", .baseColor = {0.80f, 0.80f, 0.78f}},
      {.name = "Ceiling", .baseColor = {0.85f, 0.85f, 0.85f}},
      clearGlass(),
  };
  constexpr double kCell = 0.25;
  const dvec3 lo{-2.0, 0.0, -2.5}, hi{2.0, 2.7, 2.5};
  // West wall (x = −2), in its panel coordinates u = z, v = y; centred south of the middle so that the
  // late-afternoon sun lands on the east wall.
  const Rect window{0.25, 1.75, 1.0, 2.2};
  const int room = m.addNode({.name = "Room"});
  const auto inward = [&](Face f, std::vector<Rect> holes = {}) {
    Panel p = boxFace(lo, hi, f);
    p.back = true;
    p.holes = std::move(holes);
    return p;
  };
  addPanel(m.prim(m.meshOf(m.addMeshNode("Floor", room)), "Floor"), inward(Face::kNegY), kCell);
  addPanel(m.prim(m.meshOf(m.addMeshNode("Ceiling", room)), "Ceiling"), inward(Face::kPosY), kCell);
  const int walls = m.meshOf(m.addMeshNode("Walls", room));
  for (Face f : {Face::kPosX, Face::kPosZ, Face::kNegZ}) addPanel(m.prim(walls, "Wall"), inward(f), kCell);
  addPanel(m.prim(walls, "Wall"), inward(Face::kNegX, {window}), kCell);
  // The pane fills the opening in the wall's plane; its front faces out (west).
  Panel pane = boxFace(lo, hi, Face::kNegX);
  std::tie(pane.u0, pane.u1, pane.v0, pane.v1) = std::tuple{window.u0, window.u1, window.v0, window.v1};
  addPanel(m.prim(m.meshOf(m.addMeshNode("Window", room)), "Glass"), pane, kCell);
  return m;
}

// 2. cornell-box: the Cornell box from its measured data (Cornell University Program of Computer Graphics,
// "Cornell Box Data", mm → m). The box is open towards −Z, where the camera is; +X is the red wall, on the
// image's left.
Model cornellBox() {
  Model m{.name = "cornell-box"};
  // Diffuse reflectances: the usual RGB fits of the measured spectra. The light: emissiveFactor 1 ×
  // KHR_materials_emissive_strength 10 000 = 10 000 cd/m² over 0.130 × 0.105 m (≈ 429 lm, Lambertian).
  m.materials = {
      {.name = "White", .baseColor = {0.73f, 0.73f, 0.73f}},
      {.name = "Red", .baseColor = {0.63f, 0.065f, 0.05f}},
      {.name = "Green", .baseColor = {0.14f, 0.45f, 0.091f}},
      {.name = "Light",
       .baseColor = {0.78f, 0.78f, 0.78f},
       .emissive = {1.0f, 1.0f, 1.0f},
       .emissiveStrength = 10000.0f},
  };
  constexpr double kCell = 0.05;
  const auto mm = [](double x, double y, double z) { return dvec3{x, y, z} * 0.001; };
  const int box = m.addNode({.name = "CornellBox"});
  addPatch(m.prim(m.meshOf(m.addMeshNode("Floor", box)), "White"),
           {mm(552.8, 0, 0), mm(0, 0, 0), mm(0, 0, 559.2), mm(549.6, 0, 559.2)}, {0, 1, 0}, kCell);
  // The ceiling has a hole where the light is, so that the two never overlap.
  const Rect lightRect{0.213, 0.343, 0.227, 0.332};
  const Panel ceiling{.origin = mm(0, 548.8, 0),
                      .uAxis = {1, 0, 0},
                      .vAxis = {0, 0, 1},
                      .u0 = 0.0,
                      .u1 = 0.556,
                      .v0 = 0.0,
                      .v1 = 0.5592,
                      .holes = {lightRect}};
  addPanel(m.prim(m.meshOf(m.addMeshNode("Ceiling", box)), "White"), ceiling, kCell);
  addPatch(m.prim(m.meshOf(m.addMeshNode("BackWall", box)), "White"),
           {mm(549.6, 0, 559.2), mm(0, 0, 559.2), mm(0, 548.8, 559.2), mm(556, 548.8, 559.2)}, {0, 0, -1},
           kCell);
  addPatch(m.prim(m.meshOf(m.addMeshNode("RightWall", box)), "Green"),
           {mm(0, 0, 559.2), mm(0, 0, 0), mm(0, 548.8, 0), mm(0, 548.8, 559.2)}, {1, 0, 0}, kCell);
  addPatch(m.prim(m.meshOf(m.addMeshNode("LeftWall", box)), "Red"),
           {mm(552.8, 0, 0), mm(549.6, 0, 559.2), mm(556, 548.8, 559.2), mm(556, 548.8, 0)}, {-1, 0, 0},
           kCell);
  addPrism(m.prim(m.meshOf(m.addMeshNode("ShortBlock", box)), "White"),
           {{0.130, 0.065}, {0.082, 0.225}, {0.240, 0.272}, {0.290, 0.114}}, 0.0, 0.165, kCell);
  addPrism(m.prim(m.meshOf(m.addMeshNode("TallBlock", box)), "White"),
           {{0.423, 0.247}, {0.265, 0.296}, {0.314, 0.456}, {0.472, 0.406}}, 0.0, 0.330, kCell);
  // The light faces down; a single-sided emitter emits from its front only.
  Panel light = ceiling;
  std::tie(light.u0, light.u1, light.v0, light.v1) =
      std::tuple{lightRect.u0, lightRect.u1, lightRect.v0, lightRect.v1};
  light.holes.clear();
  addPanel(m.prim(m.meshOf(m.addMeshNode("Light", box)), "Light"), light, kCell);
  return m;
}

// One wall of a house with thickness: the outer face, the inner face and the reveals of its openings. The
// outer face is origin + u·uAxis + v·vAxis with uAxis × vAxis pointing outwards; the inner face lies
// `thicknessM` inwards.
struct ThickWall {
  dvec3 origin, uAxis, vAxis;
  double outerU0, outerU1, outerV0, outerV1;
  double innerU0, innerU1, innerV0, innerV1;
  std::vector<Rect> openings;
};

void addThickWall(Primitive& outer, Primitive& inner, const ThickWall& w, double thicknessM, double cellM) {
  const dvec3 out = glm::cross(w.uAxis, w.vAxis);
  std::vector<double> ub, vb;
  for (const Rect& o : w.openings) {
    ub.insert(ub.end(), {o.u0, o.u1});
    vb.insert(vb.end(), {o.v0, o.v1});
  }
  // Both faces and the reveals split each opening's edges at the same grid lines (same breaks and cells).
  addPanel(outer, {w.origin, w.uAxis, w.vAxis, w.outerU0, w.outerU1, w.outerV0, w.outerV1, w.openings},
           cellM);
  const Panel inside{.origin = w.origin - thicknessM * out,
                     .uAxis = w.uAxis,
                     .vAxis = w.vAxis,
                     .u0 = w.innerU0,
                     .u1 = w.innerU1,
                     .v0 = w.innerV0,
                     .v1 = w.innerV1,
                     .holes = w.openings,
                     .back = true};
  addPanel(inner, inside, cellM);
  for (const Rect& o : w.openings) {
    // Sill (front up), head (front down), the side at u0 (front +u) and the side at u1 (front −u).
    const dvec3 sill = w.origin + o.v0 * w.vAxis, head = w.origin + o.v1 * w.vAxis;
    addPanel(outer, {sill, w.uAxis, -out, o.u0, o.u1, 0.0, thicknessM, {}, ub, {}}, cellM);
    addPanel(outer, {head, w.uAxis, -out, o.u0, o.u1, 0.0, thicknessM, {}, ub, {}, true}, cellM);
    addPanel(outer, {w.origin + o.u0 * w.uAxis, -out, w.vAxis, 0.0, thicknessM, o.v0, o.v1, {}, {}, vb},
             cellM);
    addPanel(outer, {w.origin + o.u1 * w.uAxis, -out, w.vAxis, 0.0, thicknessM, o.v0, o.v1, {}, {}, vb, true},
             cellM);
  }
}

// 3. house: a one-storey house 8 m (x) × 6 m (z) with a gable roof (ridge along x), a door and five windows,
// on a 60 × 60 m ground with two trees and a low garden wall. The front (door) faces south (+Z).
Model house() {
  Model m{.name = "house"};
  m.materials = {
      {.name = "Walls", .baseColor = {0.75f, 0.73f, 0.70f}, .roughness = 0.9f},
      {.name = "InteriorWalls", .baseColor = {0.85f, 0.85f, 0.82f}},
      {.name = "Floor", .baseColor = {0.45f, 0.32f, 0.20f}, .roughness = 0.5f},
      {.name = "Ceiling", .baseColor = {0.88f, 0.88f, 0.88f}},
      {.name = "Roof", .baseColor = {0.45f, 0.18f, 0.12f}, .roughness = 0.7f},
      clearGlass(),
      {.name = "Door", .baseColor = {0.25f, 0.15f, 0.10f}, .roughness = 0.5f},
      {.name = "Ground", .baseColor = {0.15f, 0.24f, 0.08f}},
      {.name = "Bark", .baseColor = {0.22f, 0.16f, 0.11f}},
      {.name = "Foliage", .baseColor = {0.10f, 0.28f, 0.07f}},
      {.name = "GardenWall", .baseColor = {0.50f, 0.26f, 0.18f}, .roughness = 0.9f},
  };
  constexpr double kT = 0.2;          // wall thickness
  constexpr double kFloorY = 0.15;    // interior floor, above the ground
  constexpr double kCeilingY = 2.75;  // interior ceiling
  constexpr double kEavesY = 3.0;     // top of the outer walls, where the roof's underside meets them
  constexpr double kRidgeY = 4.5;     // roof underside at the ridge (slope 1:2, 26.6°)
  constexpr double kWallCell = 0.5;
  const Rect door{1.3, 2.3, kFloorY, 2.25};

  const int houseNode = m.addNode({.name = "House"});
  const int walls = m.meshOf(m.addMeshNode("Walls", houseNode));
  // Walls in their own (u, v): south u = x, north u = −x, west u = z, east u = −z; v = y everywhere.
  const std::vector<std::pair<ThickWall, std::vector<std::string>>> wallList = {
      {{{0, 0, 3},
        {1, 0, 0},
        {0, 1, 0},
        -4,
        4,
        0,
        kEavesY,
        -3.8,
        3.8,
        kFloorY,
        kCeilingY,
        {{-3.2, -1.8, 0.95, 2.25}, {-1.0, 0.4, 0.95, 2.25}, door}},
       {"Window-South-1", "Window-South-2", ""}},
      {{{0, 0, -3},
        {-1, 0, 0},
        {0, 1, 0},
        -4,
        4,
        0,
        kEavesY,
        -3.8,
        3.8,
        kFloorY,
        kCeilingY,
        {{-2.2, -0.8, 1.05, 2.25}}},
       {"Window-North"}},
      {{{-4, 0, 0},
        {0, 0, 1},
        {0, 1, 0},
        -3,
        3,
        0,
        kEavesY,
        -2.8,
        2.8,
        kFloorY,
        kCeilingY,
        {{-0.7, 0.7, 0.95, 2.25}}},
       {"Window-West"}},
      {{{4, 0, 0},
        {0, 0, -1},
        {0, 1, 0},
        -3,
        3,
        0,
        kEavesY,
        -2.8,
        2.8,
        kFloorY,
        kCeilingY,
        {{-0.6, 0.6, 0.95, 2.25}}},
       {"Window-East"}},
  };
  const int windows = m.addNode({.name = "Windows"}, houseNode);
  for (const auto& [w, paneNames] : wallList) {
    m.prim(walls, "Walls");
    m.prim(walls, "InteriorWalls");
    auto& ps = m.meshes[static_cast<std::size_t>(walls)].primitives;
    addThickWall(ps[0], ps[1], w, kT, kWallCell);
    const dvec3 out = glm::cross(w.uAxis, w.vAxis);
    for (std::size_t i = 0; i < paneNames.size(); ++i) {
      if (paneNames[i].empty()) continue;
      // Glass 7 cm behind the outer face, front outwards.
      const Rect& o = w.openings[i];
      addPanel(m.prim(m.meshOf(m.addMeshNode(paneNames[i], windows)), "Glass"),
               {w.origin - 0.07 * out, w.uAxis, w.vAxis, o.u0, o.u1, o.v0, o.v1}, kWallCell);
    }
  }
  // The door leaf: a 5 cm slab whose edges meet the reveals, 5 cm behind the outer face of the south wall.
  const int doorMesh = m.meshOf(m.addMeshNode("Door", houseNode));
  addPanel(m.prim(doorMesh, "Door"), {{0, 0, 2.95}, {1, 0, 0}, {0, 1, 0}, door.u0, door.u1, door.v0, door.v1},
           kWallCell);
  addPanel(m.prim(doorMesh, "Door"),
           {{0, 0, 2.90}, {1, 0, 0}, {0, 1, 0}, door.u0, door.u1, door.v0, door.v1, {}, {}, {}, true},
           kWallCell);
  // Gables: the outer wall above the eaves up to the roof's underside.
  for (double s : {-1.0, 1.0}) {
    const dvec3 a{4 * s, kEavesY, 3 * s}, b{4 * s, kEavesY, -3 * s}, apex{4 * s, kRidgeY, 0};
    addTriangle(m.prim(walls, "Walls"), a, b, apex, 6);
  }
  addPanel(m.prim(m.meshOf(m.addMeshNode("Floor", houseNode)), "Floor"),
           {{0, kFloorY, 0}, {1, 0, 0}, {0, 0, -1}, -3.8, 3.8, -2.8, 2.8}, kWallCell);
  addPanel(m.prim(m.meshOf(m.addMeshNode("Ceiling", houseNode)), "Ceiling"),
           {{0, kCeilingY, 0}, {1, 0, 0}, {0, 0, -1}, -3.8, 3.8, -2.8, 2.8, {}, {}, {}, true}, kWallCell);

  // Roof: one closed slab 0.2 m thick (vertically) over both slopes, 0.5 m eaves and 0.3 m gable overhangs.
  {
    constexpr double kX = 4.3, kZ = 3.5, kThick = 0.2, kCell = 1.0;
    const double eaveY = kEavesY - 0.5 * (kZ - 3.0);
    Primitive& roof = m.prim(m.meshOf(m.addMeshNode("Roof", houseNode)), "Roof");
    for (double s : {-1.0, 1.0}) {  // s = +1: south slope, −1: north slope
      const dvec3 up{0, kThick, 0};
      const dvec3 eaveL{-kX, eaveY, kZ * s}, eaveR{kX, eaveY, kZ * s}, ridgeL{-kX, kRidgeY, 0},
          ridgeR{kX, kRidgeY, 0};
      addPatch(roof, {eaveL + up, eaveR + up, ridgeR + up, ridgeL + up}, {0, 1, 0.5 * s}, kCell);
      addPatch(roof, {eaveL, eaveR, ridgeR, ridgeL}, {0, -1, -0.5 * s}, kCell);
      addPatch(roof, {eaveL, eaveR, eaveR + up, eaveL + up}, {0, 0, s}, kCell);
      for (double x : {-1.0, 1.0}) {
        const dvec3 e{kX * x, eaveY, kZ * s}, r{kX * x, kRidgeY, 0};
        addPatch(roof, {e, r, r + up, e + up}, {x, 0, 0}, kCell);
      }
    }
  }

  // Ground: 60 × 60 m around the house; the house's footprint is left out (its walls stand on the hole's
  // edge).
  addPanel(m.prim(m.meshOf(m.addMeshNode("Ground")), "Ground"),
           {{0, 0, 0}, {1, 0, 0}, {0, 0, -1}, -30, 30, -30, 30, {{-4, 4, -3, 3}}}, 3.0);

  // Low garden wall along the south edge of the garden, 0.8 m high.
  addBox(m.prim(m.meshOf(m.addMeshNode("GardenWall")), "GardenWall"), {-12, 0, 9}, {12, 0.8, 9.3}, 1.0,
         {Face::kNegY});

  // Trees: a trunk and a crown of two boxes, the lower one turned 45°; one mesh, placed twice.
  const int tree = m.addMesh("Tree");
  addBox(m.prim(tree, "Bark"), {-0.15, 0, -0.15}, {0.15, 2.2, 0.15}, 1.0, {Face::kNegY, Face::kPosY});
  {
    Primitive& crown = m.prim(tree, "Foliage");
    const std::size_t first = crown.positions.size();
    addBox(crown, {-1.2, 2.2, -1.2}, {1.2, 4.2, 1.2}, 1.0);
    const glm::dmat3 turn = glm::mat3_cast(rotationYDeg(45.0));
    for (std::size_t i = first; i < crown.positions.size(); ++i) {
      crown.positions[i] = glm::vec3(turn * dvec3(crown.positions[i]));
      crown.normals[i] = glm::vec3(turn * dvec3(crown.normals[i]));
    }
    addBox(crown, {-0.8, 4.2, -0.8}, {0.8, 5.4, 0.8}, 1.0, {Face::kNegY});
  }
  m.addNode({.name = "Tree-SouthWest", .mesh = tree, .translation = {-9, 0, 5}});
  m.addNode({.name = "Tree-NorthEast",
             .mesh = tree,
             .translation = {10, 0, -8},
             .rotation = rotationYDeg(20.0),
             .scale = 1.25});
  return m;
}

// 4. open-surfaces: two-sided open surfaces under the sun: a pergola with a thin canopy, a freestanding
// screen wall, a tilted shade sail and a shrub of leaf quads, on a 20 × 20 m ground.
Model openSurfaces() {
  Model m{.name = "open-surfaces"};
  m.materials = {
      {.name = "Ground", .baseColor = {0.30f, 0.28f, 0.25f}},
      {.name = "Timber", .baseColor = {0.50f, 0.36f, 0.22f}, .roughness = 0.8f},
      {.name = "Canopy", .baseColor = {0.70f, 0.70f, 0.68f}, .roughness = 0.6f, .doubleSided = true},
      {.name = "Screen", .baseColor = {0.60f, 0.60f, 0.60f}, .doubleSided = true},
      {.name = "Sail", .baseColor = {0.85f, 0.82f, 0.75f}, .doubleSided = true},
      {.name = "Leaf", .baseColor = {0.12f, 0.35f, 0.08f}, .roughness = 0.7f, .doubleSided = true},
  };
  addPanel(m.prim(m.meshOf(m.addMeshNode("Ground")), "Ground"),
           {{0, 0, 0}, {1, 0, 0}, {0, 0, -1}, -10, 10, -10, 10}, 1.0);

  // Pergola 3 × 4 m: four posts up to the canopy, a single-plane canopy at 2.5 m (front up).
  const int pergola = m.addNode({.name = "Pergola"});
  Primitive& posts = m.prim(m.meshOf(m.addMeshNode("Posts", pergola)), "Timber");
  for (double x : {-1.5, 1.5}) {
    for (double z : {-2.0, 2.0}) {
      const double px = x - 0.06 * x / 1.5, pz = z - 0.06 * z / 2.0;  // inside the canopy's edge
      addBox(posts, {px - 0.06, 0, pz - 0.06}, {px + 0.06, 2.5, pz + 0.06}, 0.25, {Face::kNegY, Face::kPosY});
    }
  }
  addPanel(m.prim(m.meshOf(m.addMeshNode("Canopy", pergola)), "Canopy"),
           {{0, 2.5, 0}, {1, 0, 0}, {0, 0, -1}, -1.5, 1.5, -2.0, 2.0}, 0.25);

  // Freestanding screen wall 4 × 2.2 m north of the pergola, front to the south (sunlit at noon, its back
  // shaded).
  addPanel(m.prim(m.meshOf(m.addMeshNode("Screen")), "Screen"),
           {{0, 0, -4}, {1, 0, 0}, {0, 1, 0}, -2, 2, 0, 2.2}, 0.25);

  // Shade sail: a triangle stretched between three points at 2.2–2.9 m, front up.
  addTriangle(m.prim(m.meshOf(m.addMeshNode("Sail")), "Sail"), {-6.0, 2.9, 3.0}, {-2.5, 2.2, 4.5},
              {-4.0, 2.5, 0.0}, 8);

  // Shrub: 20 leaves of 0.40 × 0.16 m on a golden-angle spiral, 8 cm apart in height, tilted 10–34° down from
  // horizontal (so that no two leaves intersect), front up.
  {
    Primitive& leaves = m.prim(m.meshOf(m.addMeshNode("Leaves")), "Leaf");
    const dvec3 base{3.5, 0.0, 2.0};
    for (int i = 0; i < 20; ++i) {
      const double yaw = glm::radians(137.50776 * i), tilt = glm::radians(10.0 + 8.0 * (i % 4));
      const dvec3 radial{std::cos(yaw), 0, std::sin(yaw)};
      const dvec3 side = glm::cross(dvec3{0, 1, 0}, radial);
      const dvec3 along = std::cos(tilt) * radial - std::sin(tilt) * dvec3{0, 1, 0};
      const dvec3 root = base + (0.10 + 0.02 * i) * radial + dvec3{0, 0.5 + 0.08 * i, 0};
      const dvec3 a = root - 0.08 * side, b = root + 0.08 * side;
      addPatch(leaves, {a, b, b + 0.4 * along, a + 0.4 * along}, glm::cross(along, side), 1.0);
    }
  }
  return m;
}

// 5. two-storey: a two-storey block 6 m (x) × 8 m (z), 5.8 m high, of inward-facing surfaces without
// thickness (as box-room): a ground floor (floor y = 0, ceiling 2.8 m) and an upper floor (floor 3.0 m,
// ceiling 5.8 m) with windows south (+Z) and west (−X) on both storeys. The scene for per-storey plans.
Model twoStorey() {
  Model m{.name = "two-storey"};
  m.materials = {
      {.name = "Floor", .baseColor = {0.45f, 0.32f, 0.20f}, .roughness = 0.5f},
      {.name = "Wall", .baseColor = {0.80f, 0.80f, 0.78f}},
      {.name = "Ceiling", .baseColor = {0.85f, 0.85f, 0.85f}},
      clearGlass(),
  };
  constexpr double kCell = 0.4;
  constexpr double kGroundCeilingY = 2.8, kUpperFloorY = 3.0;
  const dvec3 lo{-3.0, 0.0, -4.0}, hi{3.0, 5.8, 4.0};
  // Openings in each facade's panel coordinates (boxFace: south u = x, west u = z; v = y).
  const std::vector<Rect> south{{-2.0, -0.5, 0.9, 2.3}, {0.5, 2.0, 0.9, 2.3}, {-2.0, 2.0, 3.9, 5.3}};
  const std::vector<Rect> west{{-2.0, 0.0, 0.9, 2.3}, {0.0, 2.0, 3.9, 5.3}};
  const int building = m.addNode({.name = "Building"});
  const auto inward = [&](dvec3 boxLo, dvec3 boxHi, Face f, std::vector<Rect> holes = {}) {
    Panel p = boxFace(boxLo, boxHi, f);
    p.back = true;
    p.holes = std::move(holes);
    p.vBreaks = {kGroundCeilingY, kUpperFloorY};
    return p;
  };
  const int floors = m.meshOf(m.addMeshNode("Floors", building));
  addPanel(m.prim(floors, "Floor"), inward(lo, hi, Face::kNegY), kCell);
  addPanel(m.prim(floors, "Floor"), inward({lo.x, kUpperFloorY, lo.z}, hi, Face::kNegY), kCell);
  const int ceilings = m.meshOf(m.addMeshNode("Ceilings", building));
  addPanel(m.prim(ceilings, "Ceiling"), inward(lo, {hi.x, kGroundCeilingY, hi.z}, Face::kPosY), kCell);
  addPanel(m.prim(ceilings, "Ceiling"), inward(lo, hi, Face::kPosY), kCell);
  const int walls = m.meshOf(m.addMeshNode("Walls", building));
  addPanel(m.prim(walls, "Wall"), inward(lo, hi, Face::kPosZ, south), kCell);
  addPanel(m.prim(walls, "Wall"), inward(lo, hi, Face::kNegX, west), kCell);
  for (Face f : {Face::kPosX, Face::kNegZ}) addPanel(m.prim(walls, "Wall"), inward(lo, hi, f), kCell);
  // The panes fill the openings in the walls' planes; their fronts face out.
  Primitive& panes = m.prim(m.meshOf(m.addMeshNode("Windows", building)), "Glass");
  for (const auto& [face, openings] : {std::pair{Face::kPosZ, south}, std::pair{Face::kNegX, west}}) {
    for (const Rect& o : openings) {
      Panel pane = boxFace(lo, hi, face);
      std::tie(pane.u0, pane.u1, pane.v0, pane.v1) = std::tuple{o.u0, o.u1, o.v0, o.v1};
      addPanel(panes, pane, kCell);
    }
  }
  return m;
}

// -----------------------------------------------------------------------------------------------------------
// glTF writing

// The shortest decimal that reads back as `f`, as a double that nlohmann::json prints as that decimal.
double num(float f) {
  char text[32];
  const auto [end, ec] = std::to_chars(text, text + sizeof text - 1, f);
  if (ec != std::errc()) throw std::runtime_error("to_chars failed");
  *end = '\0';
  return std::strtod(text, nullptr);
}

Json vec(glm::vec3 v) {
  return Json::array({num(v.x), num(v.y), num(v.z)});
}

class Writer {
 public:
  Json accessors = Json::array(), bufferViews = Json::array();
  std::vector<unsigned char> bin;

  // Appends `bytes` as a new buffer view (4-byte aligned) and returns its index.
  int view(const void* data, std::size_t bytes, int target) {
    while (bin.size() % 4 != 0) bin.push_back(0);
    Json v;
    v["buffer"] = 0;
    v["byteOffset"] = bin.size();
    v["byteLength"] = bytes;
    v["target"] = target;
    const auto* p = static_cast<const unsigned char*>(data);
    bin.insert(bin.end(), p, p + bytes);
    bufferViews.push_back(std::move(v));
    return static_cast<int>(bufferViews.size() - 1);
  }
  template <class V>
  int floatAccessor(const std::vector<V>& data, const char* type, bool withBounds) {
    constexpr int kArrayBuffer = 34962, kFloat = 5126;
    Json a;
    a["bufferView"] = view(data.data(), data.size() * sizeof(V), kArrayBuffer);
    a["componentType"] = kFloat;
    a["count"] = data.size();
    a["type"] = type;
    if (withBounds) {
      V lo = data.front(), hi = data.front();
      for (const V& d : data) {
        lo = glm::min(lo, d);
        hi = glm::max(hi, d);
      }
      Json jl = Json::array(), jh = Json::array();
      for (int i = 0; i < V::length(); ++i) {
        jl.push_back(num(lo[i]));
        jh.push_back(num(hi[i]));
      }
      a["min"] = std::move(jl);
      a["max"] = std::move(jh);
    }
    accessors.push_back(std::move(a));
    return static_cast<int>(accessors.size() - 1);
  }
  int indexAccessor(const std::vector<std::uint32_t>& indices, std::size_t vertexCount) {
    constexpr int kElementArrayBuffer = 34963, kUnsignedShort = 5123, kUnsignedInt = 5125;
    Json a;
    if (vertexCount <= 65535) {
      const std::vector<std::uint16_t> shorts(indices.begin(), indices.end());
      a["bufferView"] = view(shorts.data(), shorts.size() * 2, kElementArrayBuffer);
      a["componentType"] = kUnsignedShort;
    } else {
      a["bufferView"] = view(indices.data(), indices.size() * 4, kElementArrayBuffer);
      a["componentType"] = kUnsignedInt;
    }
    a["count"] = indices.size();
    a["type"] = "SCALAR";
    accessors.push_back(std::move(a));
    return static_cast<int>(accessors.size() - 1);
  }
};

void writeFile(const fs::path& path, const void* data, std::size_t bytes) {
  std::ofstream f(path, std::ios::binary | std::ios::trunc);
  f.write(static_cast<const char*>(data), static_cast<std::streamsize>(bytes));
  if (!f) throw std::runtime_error("cannot write " + path.string());
}

// Writes dir/<name>.gltf and dir/<name>.bin; returns the .gltf path.
fs::path writeModel(const Model& m, const fs::path& dir) {
  Writer w;
  std::vector<std::string> extensions;
  const auto use = [&](const char* ext) {
    if (std::find(extensions.begin(), extensions.end(), ext) == extensions.end()) extensions.push_back(ext);
  };

  Json materials = Json::array();
  for (const Material& mat : m.materials) {
    Json j;
    j["name"] = mat.name;
    j["pbrMetallicRoughness"] = {
        {"baseColorFactor", {num(mat.baseColor.r), num(mat.baseColor.g), num(mat.baseColor.b), 1.0}},
        {"metallicFactor", 0.0},
        {"roughnessFactor", num(mat.roughness)}};
    if (mat.emissive != glm::vec3(0.0f)) j["emissiveFactor"] = vec(mat.emissive);
    if (mat.doubleSided) j["doubleSided"] = true;
    Json ext = Json::object();
    if (mat.emissiveStrength != 1.0f) {
      ext["KHR_materials_emissive_strength"] = {{"emissiveStrength", num(mat.emissiveStrength)}};
    }
    if (mat.transmission > 0.0f) {
      ext["KHR_materials_transmission"] = {{"transmissionFactor", num(mat.transmission)}};
    }
    if (mat.ior > 0.0f) ext["KHR_materials_ior"] = {{"ior", num(mat.ior)}};
    for (const auto& [key, value] : ext.items()) use(key.c_str());
    if (!ext.empty()) j["extensions"] = std::move(ext);
    materials.push_back(std::move(j));
  }
  const auto materialIndex = [&](const std::string& name) {
    for (std::size_t i = 0; i < m.materials.size(); ++i) {
      if (m.materials[i].name == name) return static_cast<int>(i);
    }
    throw std::logic_error("no material " + name);
  };

  Json meshes = Json::array();
  for (const Mesh& mesh : m.meshes) {
    Json prims = Json::array();
    for (const Primitive& p : mesh.primitives) {
      if (p.indices.empty()) throw std::logic_error(m.name + "/" + mesh.name + ": empty primitive");
      Json attributes;
      attributes["POSITION"] = w.floatAccessor(p.positions, "VEC3", true);
      attributes["NORMAL"] = w.floatAccessor(p.normals, "VEC3", false);
      attributes["TEXCOORD_0"] = w.floatAccessor(p.uvs, "VEC2", false);
      Json jp;
      jp["attributes"] = std::move(attributes);
      jp["indices"] = w.indexAccessor(p.indices, p.positions.size());
      jp["material"] = materialIndex(p.material);
      prims.push_back(std::move(jp));
    }
    meshes.push_back({{"name", mesh.name}, {"primitives", std::move(prims)}});
  }

  Json nodes = Json::array();
  for (const Node& n : m.nodes) {
    Json j;
    j["name"] = n.name;
    if (n.mesh >= 0) j["mesh"] = n.mesh;
    if (!n.children.empty()) j["children"] = n.children;
    if (n.translation != dvec3(0.0)) j["translation"] = vec(glm::vec3(n.translation));
    if (n.rotation != glm::dquat(1.0, 0.0, 0.0, 0.0)) {
      const glm::quat q(n.rotation);
      j["rotation"] = {num(q.x), num(q.y), num(q.z), num(q.w)};
    }
    if (n.scale != 1.0) j["scale"] = vec(glm::vec3(static_cast<float>(n.scale)));
    nodes.push_back(std::move(j));
  }

  const std::string binName = m.name + ".bin";
  Json gltf;
  gltf["asset"] = {{"version", "2.0"}, {"generator", "fly tests/tools/make_scenes.cpp"}};
  if (!extensions.empty()) gltf["extensionsUsed"] = extensions;
  gltf["scene"] = 0;
  gltf["scenes"] = Json::array({{{"name", m.name}, {"nodes", m.roots}}});
  gltf["nodes"] = std::move(nodes);
  gltf["meshes"] = std::move(meshes);
  gltf["materials"] = std::move(materials);
  gltf["accessors"] = std::move(w.accessors);
  gltf["bufferViews"] = std::move(w.bufferViews);
  gltf["buffers"] = Json::array({{{"byteLength", w.bin.size()}, {"uri", binName}}});

  fs::create_directories(dir);
  const std::string text = gltf.dump(2) + "\n";
  const fs::path gltfPath = dir / (m.name + ".gltf");
  writeFile(gltfPath, text.data(), text.size());
  writeFile(dir / binName, w.bin.data(), w.bin.size());
  return gltfPath;
}

// -----------------------------------------------------------------------------------------------------------
// Read-back check

template <class T, int kComponentType, int kType>
std::vector<T> readAccessor(const tinygltf::Model& model, int index, const std::string& where) {
  if (index < 0 || index >= static_cast<int>(model.accessors.size()))
    throw std::runtime_error(where + ": no accessor");
  const tinygltf::Accessor& a = model.accessors[static_cast<std::size_t>(index)];
  if (a.componentType != kComponentType || a.type != kType || a.bufferView < 0) {
    throw std::runtime_error(where + ": unexpected accessor type");
  }
  const tinygltf::BufferView& v = model.bufferViews[static_cast<std::size_t>(a.bufferView)];
  const tinygltf::Buffer& b = model.buffers[static_cast<std::size_t>(v.buffer)];
  const int stride = a.ByteStride(v);
  if (stride <= 0) throw std::runtime_error(where + ": bad stride");
  const std::size_t begin = v.byteOffset + a.byteOffset;
  if (a.count > 0 &&
      (begin + (a.count - 1) * static_cast<std::size_t>(stride) + sizeof(T) > v.byteOffset + v.byteLength ||
       v.byteOffset + v.byteLength > b.data.size())) {
    throw std::runtime_error(where + ": accessor outside its buffer");
  }
  std::vector<T> out(a.count);
  for (std::size_t i = 0; i < a.count; ++i) {
    std::memcpy(&out[i], b.data.data() + begin + i * static_cast<std::size_t>(stride), sizeof(T));
  }
  return out;
}

struct Counts {
  std::size_t triangles = 0, vertices = 0;
};

// Reads `path` back with tinygltf and checks what the sample scenes promise.
Counts check(const fs::path& path) {
  tinygltf::Model model;
  tinygltf::TinyGLTF loader;
  std::string err, warn;
  const std::string where = path.filename().string();
  if (!loader.LoadASCIIFromFile(&model, &err, &warn, path.string())) {
    throw std::runtime_error(where + ": tinygltf cannot load it: " + err);
  }
  if (!warn.empty()) throw std::runtime_error(where + ": tinygltf warns: " + warn);
  Counts counts;
  for (const tinygltf::Mesh& mesh : model.meshes) {
    for (const tinygltf::Primitive& p : mesh.primitives) {
      const std::string at = where + ": mesh " + mesh.name;
      if (p.mode != TINYGLTF_MODE_TRIANGLES) throw std::runtime_error(at + ": not triangles");
      if (p.material < 0 || p.material >= static_cast<int>(model.materials.size())) {
        throw std::runtime_error(at + ": no material");
      }
      const auto attr = [&](const char* name) {
        const auto it = p.attributes.find(name);
        if (it == p.attributes.end()) throw std::runtime_error(at + ": no " + name);
        return it->second;
      };
      const auto pos = readAccessor<glm::vec3, TINYGLTF_COMPONENT_TYPE_FLOAT, TINYGLTF_TYPE_VEC3>(
          model, attr("POSITION"), at);
      const auto nrm = readAccessor<glm::vec3, TINYGLTF_COMPONENT_TYPE_FLOAT, TINYGLTF_TYPE_VEC3>(
          model, attr("NORMAL"), at);
      const auto uv = readAccessor<glm::vec2, TINYGLTF_COMPONENT_TYPE_FLOAT, TINYGLTF_TYPE_VEC2>(
          model, attr("TEXCOORD_0"), at);
      if (nrm.size() != pos.size() || uv.size() != pos.size())
        throw std::runtime_error(at + ": attribute counts");
      std::vector<std::uint32_t> idx;
      const int ct = model.accessors[static_cast<std::size_t>(p.indices)].componentType;
      if (ct == TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT) {
        const auto s =
            readAccessor<std::uint16_t, TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT, TINYGLTF_TYPE_SCALAR>(
                model, p.indices, at);
        idx.assign(s.begin(), s.end());
      } else {
        idx = readAccessor<std::uint32_t, TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT, TINYGLTF_TYPE_SCALAR>(
            model, p.indices, at);
      }
      if (idx.size() % 3 != 0) throw std::runtime_error(at + ": index count not a multiple of 3");
      for (const glm::vec3& n : nrm) {
        if (std::abs(glm::length(n) - 1.0f) > 1e-5f)
          throw std::runtime_error(at + ": normal not unit length");
      }
      for (std::size_t t = 0; t < idx.size(); t += 3) {
        for (std::size_t k = 0; k < 3; ++k) {
          if (idx[t + k] >= pos.size()) throw std::runtime_error(at + ": index out of range");
        }
        const glm::vec3 a = pos[idx[t]], b = pos[idx[t + 1]], c = pos[idx[t + 2]];
        const glm::vec3 g = glm::cross(b - a, c - a);
        if (0.5f * glm::length(g) < 1e-6f) throw std::runtime_error(at + ": degenerate triangle");
        // Counter-clockwise front faces: the winding agrees with the vertex normals.
        const glm::vec3 gn = glm::normalize(g);
        for (std::size_t k = 0; k < 3; ++k) {
          if (glm::dot(gn, nrm[idx[t + k]]) < 0.99f)
            throw std::runtime_error(at + ": winding and normal disagree");
        }
      }
      counts.triangles += idx.size() / 3;
      counts.vertices += pos.size();
    }
  }
  return counts;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 2) {
    std::fprintf(stderr, "usage: make_scenes OUTDIR\n  writes OUTDIR/<scene>/<scene>.gltf and .bin\n");
    return 2;
  }
  try {
    const fs::path outDir = argv[1];
    for (const Model& model : {boxRoom(), cornellBox(), house(), openSurfaces(), twoStorey()}) {
      const Counts c = check(writeModel(model, outDir / model.name));
      std::printf("%-14s %5zu triangles %6zu vertices %3zu materials %3zu nodes\n", model.name.c_str(),
                  c.triangles, c.vertices, model.materials.size(), model.nodes.size());
    }
  } catch (const std::exception& e) {
    std::fprintf(stderr, "make_scenes: %s\n", e.what());
    return 1;
  }
  return 0;
}
