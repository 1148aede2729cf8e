// The specular environment of glossy surfaces seen from where the viewer stands (a reflection probe, as
// real-time engines place in rooms): a cube map of the scene captured at the eye, GGX-prefiltered as a cube
// reflector's is (raster/cube_reflections.h), and a box fitted to what it sees, so that a surface at p looks
// up the probe towards where its mirror ray r leaves the box (parallax correction: Lagarde & Zanuttini,
// "Local image-based lighting with parallax-corrected cubemap", SIGGRAPH 2012 talk) rather than along r from
// the probe's centre. Indoors a polished floor then reflects the room's walls, ceiling and windows instead of
// the open sky; outdoors the box's open sides lie at infinity and the lookup is the plain direction.
//
// The box: per axis direction ±x, ±y, ±z, the median distance along that axis to what the face's central
// half (|s|, |t| < ½) shows; where more than half of it is sky, that side is open (kOpenSideM). For a
// rectangular room seen from inside this is the room itself; furniture in the middle of a face moves the
// median only where it covers more than half of the face's centre.
//
// The renderer captures a probe before a frame of light-map or sunlight mode where the scene has a sky and a
// material with a specular environment part, when the eye has moved more than kRecaptureDistanceM from the
// probe's centre, or when the scene, its light or the mode changed (Renderer::render). Needs a current
// context.
#pragma once

#include <array>
#include <functional>

#include "raster/cube_reflections.h"

namespace fly::raster {

// Distance of an open side of the probe's box, m: beyond any scene's extent, so that the lookup direction
// is the mirror direction.
inline constexpr float kOpenSideM = 1e6f;
// The eye moves this far from the probe's centre before the probe is captured again, m.
inline constexpr float kRecaptureDistanceM = 0.25f;

class RoomProbe {
 public:
  explicit RoomProbe(EnvironmentLight::Compile compile);

  // A face drawn for capture: its luminance image (as CubeReflections::Face) and its depth buffer read back
  // (facePx² values in [0, 1], rows from the bottom; 1 = nothing drawn: the sky).
  struct Face {
    unsigned luminance = 0;
    std::vector<float> depth;
  };
  // Captures the probe at centreM: drawFace(view) draws one face into a facePx()² target.
  void capture(const vec3& centreM, const std::function<Face(const View&)>& drawFace);
  uint32_t facePx() const { return cube_.facePx(); }
  bool captured() const { return captured_; }
  const EnvironmentLight& maps() const { return cube_.maps(0); }
  const vec3& centreM() const { return centreM_; }
  const vec3& boxMinM() const { return boxMinM_; }
  const vec3& boxMaxM() const { return boxMaxM_; }

  // The box side along face f's direction (f = 0 … 5: +X, −X, +Y, −Y, +Z, −Z): the median axial distance of
  // the depth image's central half, or kOpenSideM where more than half of it is sky. depth: facePx² values
  // of a 90° perspective view with near plane nearM and far plane at infinity (CubeReflections::faceView).
  static float sideDistanceM(const std::vector<float>& depth, uint32_t facePx, float nearM);

 private:
  CubeReflections cube_;
  bool captured_ = false;
  vec3 centreM_{0.0f}, boxMinM_{-kOpenSideM}, boxMaxM_{kOpenSideM};
};

}  // namespace fly::raster
