#pragma once

#include <Eigen/Core>

namespace incise::render {

// A pinhole camera in world coordinates [m]: it sits at eye, looks at target, and up points to
// the top of the image.
struct Camera {
  Eigen::Vector3d eye{0.0, 0.0, 0.5};
  Eigen::Vector3d target{0.0, 0.0, 0.0};
  Eigen::Vector3d up{0.0, 1.0, 0.0};
  double fov_y_deg = 45.0;  // full vertical field of view, in (0, 180)
  double near_m = 0.01;     // clip distances along the view direction, 0 < near_m < far_m
  double far_m = 10.0;
  // An endoscope's camera carries its light: a point light at the eye (the "headlight") whose
  // diffuse and specular terms fall off as 1 / (1 + (d / light_falloff_m)^2), d the distance from
  // the eye; the scene is then drawn without a floor, on the cavity's dark backdrop
  // (SceneRenderer). Without it, the scene's directional light and floor.
  bool headlight = false;
  double light_falloff_m = 0.08;  // > 0 when headlight
  // The instruments' shadows (SceneRenderer) are cast, under a headlight, from this far below the
  // eye in the image [m]: a light exactly at the eye would hide every shadow behind its caster, and
  // the gap between an instrument and its shadow, closing as it nears the tissue, is the depth cue
  // trainees learn to read. The lighting itself stays at the eye.
  double shadow_light_offset_m = 0.02;
};

// World -> eye transform as gluLookAt builds it: right-handed, the camera looks down -z.
// Throws std::invalid_argument if eye == target or up is parallel to the view direction.
Eigen::Matrix4d view_matrix(const Camera& camera);

// Eye -> clip transform as gluPerspective builds it (depth maps to [-1, 1], OpenGL's convention).
// aspect: image width / height. Throws std::invalid_argument for a non-positive aspect, a field of
// view outside (0, 180) or clip distances that do not satisfy 0 < near_m < far_m.
Eigen::Matrix4d projection_matrix(const Camera& camera, double aspect);

}  // namespace incise::render
