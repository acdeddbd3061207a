// How the tissue reads: each label in its own look, vessels fixed to the tissue (stable at rest,
// moving with it rather than swimming over it), and a task's zones as translucent balls.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdlib>
#include <span>
#include <stdexcept>
#include <vector>

#include "gl_test.h"
#include "scene_test_util.h"
#include "sim/render/scene_renderer.h"

namespace incise::render {
namespace {

using test::colour_error;
using test::pixel_at;
using test::PixelPosition;
using test::Positions;
using test::project;
using test::square_surface;
using test::Surface;

using TissueLookTest = GlTest;

constexpr int kWidth = 640;
constexpr int kHeight = 480;

Camera oblique_camera(const Eigen::Vector3d& shift = Eigen::Vector3d::Zero()) {
  Camera camera;
  camera.eye = Eigen::Vector3d(0.0, -0.06, 0.12) + shift;
  camera.target = Eigen::Vector3d(0.0, 0.0, 0.03) + shift;
  camera.up = Eigen::Vector3d::UnitZ();
  camera.fov_y_deg = 40;
  return camera;
}

// 4 cm square at z = 3 cm; per face 1 left of x = 0, 2 right of it.
struct LabelledSquare {
  Surface surface =
      square_surface(0.02, 16, Eigen::Matrix3d::Identity(), Eigen::Vector3d(0, 0, 0.03));
  std::vector<std::uint8_t> labels;
  LabelledSquare() {
    for (Eigen::Index f = 0; f < surface.F.rows(); ++f) {
      double x = 0;
      for (int k = 0; k < 3; ++k)
        x += surface.V(surface.F(f, k), 0) / 3;
      labels.push_back(x < 0 ? 1 : 2);
    }
  }
  TissueView view() const {
    TissueView v = surface.view();
    v.face_labels = &labels;
    return v;
  }
};

std::vector<std::uint8_t> draw(SceneRenderer& renderer, const Framebuffer& target,
                               const Camera& camera, const TissueView& tissue,
                               std::span<const MarkView> marks = {}) {
  renderer.render(target, camera, tissue, std::span<const ToolView>{}, marks);
  return target.read_rgb();
}

// The pixels of the tissue's inner square [-h, h] x [-h, h] at z = 3 cm whose x has the sign.
std::vector<PixelPosition> half_pixels(const Camera& camera, double sign) {
  std::vector<PixelPosition> out;
  for (double x = 0.002; x <= 0.016; x += 0.0005)
    for (double y = -0.016; y <= 0.016; y += 0.0005)
      out.push_back(project(camera, kWidth, kHeight, Eigen::Vector3d(sign * x, y, 0.03)));
  return out;
}

TEST_F(TissueLookTest, EachLabelIsDrawnInItsOwnLook) {
  SceneStyle style;
  style.tissue_by_label[2] = {{0.30f, 0.60f, 0.90f}, 0.2f, 30.0f};
  SceneRenderer renderer(style);
  const Framebuffer target(kWidth, kHeight);
  const Camera camera = oblique_camera();
  const LabelledSquare square;
  const std::vector<std::uint8_t> rgb = draw(renderer, target, camera, square.view());
  for (const double x : {-0.012, 0.012}) {
    const Eigen::Vector3d p(x, 0.003, 0.03);
    const PixelPosition at = project(camera, kWidth, kHeight, p);
    const Eigen::Vector3d v = (camera.eye - p).normalized();
    const SurfaceLook& look =
        x > 0 ? renderer.style().tissue_by_label.at(2) : renderer.style().tissue;
    EXPECT_LE(colour_error(pixel_at(rgb, kWidth, at.row, at.column),
                           test::shade(renderer.style(), look, Eigen::Vector3d::UnitZ(), v)),
              4.0)
        << x;
  }
  // Labels without a look of their own, and no labels at all, are the tissue's look.
  SceneRenderer plain_renderer;
  const std::vector<std::uint8_t> plain =
      draw(plain_renderer, target, camera, square.surface.view());
  EXPECT_EQ(draw(plain_renderer, target, camera, square.view()), plain);

  std::vector<std::uint8_t> short_labels = square.labels;
  short_labels.pop_back();
  TissueView bad = square.view();
  bad.face_labels = &short_labels;
  EXPECT_THROW(draw(renderer, target, camera, bad), std::invalid_argument);
  style.tissue_by_label[3].vessels = 1.5f;
  EXPECT_THROW(SceneRenderer{style}, std::invalid_argument);
}

// Vessels in pure blue on label 1 only: a share of its pixels turn blue (lines, not a wash), none
// of label 2's do, and two frames at rest are the same bytes.
TEST_F(TissueLookTest, VesselsCoverPartOfTheirTissueOnlyAndStandStillAtRest) {
  SceneStyle style;
  style.tissue_by_label[1] = style.tissue;
  style.tissue_by_label[1].vessels = 1.0f;
  style.tissue_by_label[1].vessel_spacing_m = 0.008f;
  style.tissue_by_label[1].vessel_albedo = {0.0f, 0.0f, 1.0f};
  SceneRenderer renderer(style);
  const Framebuffer target(kWidth, kHeight);
  const Camera camera = oblique_camera();
  const LabelledSquare square;
  const std::vector<std::uint8_t> rgb = draw(renderer, target, camera, square.view());
  const auto blue_share = [&](double sign) {
    int blue = 0;
    const std::vector<PixelPosition> pixels = half_pixels(camera, sign);
    for (const PixelPosition& at : pixels) {
      const test::Pixel p = pixel_at(rgb, kWidth, at.row, at.column);
      blue += p[2] > p[0] + 20 ? 1 : 0;  // the tissue itself is red over blue
    }
    return static_cast<double>(blue) / pixels.size();
  };
  EXPECT_GT(blue_share(-1), 0.03);
  EXPECT_LT(blue_share(-1), 0.6);
  EXPECT_EQ(blue_share(+1), 0.0);
  EXPECT_EQ(draw(renderer, target, camera, square.view()), rgb);
}

// The tissue and the camera moved together by 7 mm: with the rest shape given the picture is the
// same (the vessels went with the tissue); with the pattern taken from the moved positions it is
// not (they would swim over a tissue that moves).
TEST_F(TissueLookTest, VesselsMoveWithTheTissueNotOverIt) {
  SceneStyle style;
  style.tissue.vessels = 1.0f;
  style.tissue.vessel_spacing_m = 0.006f;
  SceneRenderer renderer(style);
  const Framebuffer target(kWidth, kHeight);
  const LabelledSquare square;
  const std::vector<std::uint8_t> at_rest = draw(renderer, target, oblique_camera(), square.view());

  const Eigen::Vector3d shift(0.007, 0.003, 0.0);
  Surface moved = square.surface;
  moved.V.rowwise() += shift.transpose();
  TissueView with_rest = moved.view();
  with_rest.rest = &square.surface.V;
  const std::vector<std::uint8_t> carried =
      draw(renderer, target, oblique_camera(shift), with_rest);
  const std::vector<std::uint8_t> swum =
      draw(renderer, target, oblique_camera(shift), moved.view());
  const auto share_differing = [](const std::vector<std::uint8_t>& a,
                                  const std::vector<std::uint8_t>& b) {
    int differing = 0;
    for (std::size_t i = 0; i < a.size(); i += 3) {
      int d = 0;
      for (int c = 0; c < 3; ++c)
        d = std::max(d, std::abs(int(a[i + c]) - int(b[i + c])));
      differing += d > 3 ? 1 : 0;
    }
    return static_cast<double>(differing) / (a.size() / 3);
  };
  EXPECT_LT(share_differing(at_rest, carried), 0.002);
  EXPECT_GT(share_differing(at_rest, swum), 0.02);

  Positions short_rest = square.surface.V.topRows(3);
  with_rest.rest = &short_rest;
  EXPECT_THROW(draw(renderer, target, oblique_camera(shift), with_rest), std::invalid_argument);
}

// A target's ball over the tissue blends its lit colour over what lies behind it at
// zone_opacity: picture = (1 - a) under + a opaque, pixel by pixel; a zone wholly under the
// surface does not show; ink marks stay opaque.
TEST_F(TissueLookTest, ZonesAreTranslucentBallsOverWhatLiesBehind) {
  SceneStyle style;
  SceneRenderer renderer(style);
  SceneStyle opaque_style = style;
  opaque_style.zone_opacity = 1.0f;
  SceneRenderer opaque_renderer(opaque_style);
  const Framebuffer target(kWidth, kHeight);
  const Camera camera = oblique_camera();
  const LabelledSquare square;
  const std::vector<std::uint8_t> under = draw(renderer, target, camera, square.view());
  const std::vector<MarkView> zones = {
      {Eigen::Vector3d(-0.008, 0.0, 0.03), 0.004, MarkKind::target},
      {Eigen::Vector3d(0.008, 0.0, 0.03), 0.004, MarkKind::never_zone}};
  const std::vector<std::uint8_t> blended = draw(renderer, target, camera, square.view(), zones);
  const std::vector<std::uint8_t> opaque =
      draw(opaque_renderer, target, camera, square.view(), zones);
  const double a = style.zone_opacity;
  for (const MarkView& zone : zones) {
    // The top of the dome, facing up towards the camera.
    const PixelPosition at =
        project(camera, kWidth, kHeight, zone.centre + Eigen::Vector3d(0, 0, 0.0039));
    const test::Pixel u = pixel_at(under, kWidth, at.row, at.column);
    const test::Pixel o = pixel_at(opaque, kWidth, at.row, at.column);
    const Eigen::Vector3d expected((1 - a) * u[0] + a * o[0], (1 - a) * u[1] + a * o[1],
                                   (1 - a) * u[2] + a * o[2]);
    EXPECT_LE(colour_error(pixel_at(blended, kWidth, at.row, at.column), expected), 2.0);
    EXPECT_GT(colour_error(u, Eigen::Vector3d(o[0], o[1], o[2])), 30.0);
  }
  // The target is green, the never-zone red.
  const auto top = [&](const MarkView& zone) {
    const PixelPosition at =
        project(camera, kWidth, kHeight, zone.centre + Eigen::Vector3d(0, 0, 0.0039));
    return pixel_at(opaque, kWidth, at.row, at.column);
  };
  EXPECT_GT(top(zones[0])[1], top(zones[0])[0]);
  EXPECT_GT(top(zones[1])[0], 2 * top(zones[1])[1]);

  const std::vector<MarkView> buried = {
      {Eigen::Vector3d(0.0, 0.0, 0.02), 0.004, MarkKind::protected_zone}};
  EXPECT_EQ(draw(renderer, target, camera, square.view(), buried), under);
}

}  // namespace
}  // namespace incise::render
