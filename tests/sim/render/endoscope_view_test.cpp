// What the endoscope shows, checked against the geometry it draws: the instruments' working ends
// (a scalpel's blade, a grasper's jaws), the cut walls' interior colour, and the light at the
// scope's tip.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
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
using test::project;
using test::square_surface;
using test::Surface;

using EndoscopeViewTest = GlTest;

constexpr int kWidth = 640;
constexpr int kHeight = 480;

// Looking along +y at the plane y = 0 from 10 cm, with the scope's light.
Camera side_scope(double height = 0.035) {
  Camera camera;
  camera.eye = Eigen::Vector3d(0, -0.1, height);
  camera.target = Eigen::Vector3d(0, 0, height);
  camera.up = Eigen::Vector3d::UnitZ();
  camera.fov_y_deg = 40;
  camera.headlight = true;
  return camera;
}

std::vector<std::uint8_t> draw(SceneRenderer& renderer, const Framebuffer& target,
                               const Camera& camera, std::span<const ToolView> tools,
                               const TissueView& tissue = {}) {
  renderer.render(target, camera, tissue, tools);
  return target.read_rgb();
}

double difference(const std::vector<std::uint8_t>& a, const std::vector<std::uint8_t>& b,
                  const PixelPosition& at) {
  const test::Pixel p = pixel_at(a, kWidth, at.row, at.column);
  return colour_error(pixel_at(b, kWidth, at.row, at.column), Eigen::Vector3d(p[0], p[1], p[2]));
}

// A scalpel standing on its tip at z = 3 cm, its flat facing the camera: the blade (edge on the
// axis from the tip up, body towards -x, a third of its length wide) covers its rectangle's
// pixels; beside it, below the tip, and where a probe's ball would be, the cavity shows.
TEST_F(EndoscopeViewTest, ABladesPixelsAppearWhereTheBladeProjectsAndNowhereElse) {
  SceneRenderer renderer;
  const Framebuffer target(kWidth, kHeight);
  const Camera camera = side_scope();
  ToolView scalpel;
  scalpel.shape = ToolShape::scalpel;
  scalpel.tip = Eigen::Vector3d(0, 0, 0.03);
  scalpel.shaft_direction = Eigen::Vector3d::UnitZ();
  scalpel.side = Eigen::Vector3d::UnitY();  // the flat faces the camera
  scalpel.blade_length = 0.012;
  scalpel.shaft_length = 0.1;
  const std::vector<std::uint8_t> empty = draw(renderer, target, camera, {});
  const std::vector<std::uint8_t> with = draw(renderer, target, camera, {&scalpel, 1});

  const double length = scalpel.blade_length;
  const double height = length / 3;
  int inside = 0;
  for (const double u : {0.15, 0.5, 0.85}) {
    for (const double w : {0.2, 0.5, 0.8}) {
      const Eigen::Vector3d p(-w * height, 0, 0.03 + u * length);
      EXPECT_GT(difference(empty, with, project(camera, kWidth, kHeight, p)), 60.0)
          << u << " " << w;
      ++inside;
    }
  }
  EXPECT_EQ(inside, 9);
  // The other side of the edge, below the tip, and a probe ball's place: nothing drawn.
  for (const Eigen::Vector3d& p :
       {Eigen::Vector3d(0.5 * height, 0, 0.03 + 0.5 * length),
        Eigen::Vector3d(-0.5 * height, 0, 0.027), Eigen::Vector3d(0.003, 0, 0.03),
        Eigen::Vector3d(-1.5 * height, 0, 0.03 + 0.5 * length)}) {
    EXPECT_LE(difference(empty, with, project(camera, kWidth, kHeight, p)), 2.0) << p.transpose();
  }
}

// The grasper's hinge at z = 3 cm, jaws pointing down and opening in the xz plane. On an image
// row 70 % of the way down the jaws, the cavity between them is as wide as their inner faces are
// apart there, seen past the jaws' far side: 2 tan(a / 2) (hinge - z) at depth 10 cm + half
// their width. Closed, they meet.
TEST_F(EndoscopeViewTest, TheJawsGapInThePictureFollowsTheJawAngle) {
  SceneRenderer renderer;
  const Framebuffer target(kWidth, kHeight);
  const Camera camera = side_scope(0.025);
  const std::vector<std::uint8_t> empty = draw(renderer, target, camera, {});
  const double focal = 0.5 * kHeight / std::tan(camera.fov_y_deg * std::numbers::pi / 360);
  double last_gap = -1;
  for (const double angle : {0.0, 0.3, 0.6, 0.9}) {
    ToolView grasper;
    grasper.shape = ToolShape::grasper;
    grasper.tip = Eigen::Vector3d(0, 0, 0.03);
    grasper.shaft_direction = Eigen::Vector3d::UnitZ();
    grasper.side = Eigen::Vector3d::UnitX();
    grasper.jaw_angle = angle;
    grasper.jaw_length = 0.012;
    const std::vector<std::uint8_t> with = draw(renderer, target, camera, {&grasper, 1});
    const double below = 0.7 * grasper.jaw_length * std::cos(0.5 * angle);
    const int row = project(camera, kWidth, kHeight, Eigen::Vector3d(0, 0, 0.03 - below)).row;
    // The run of untouched pixels about the image's middle column.
    const int middle = kWidth / 2;
    int left = middle, right = middle;
    const auto untouched = [&](int column) {
      return difference(empty, with, {row, column}) <= 2.0;
    };
    if (!untouched(middle)) {
      EXPECT_EQ(angle, 0.0) << "the jaws cover the axis only when closed";
      last_gap = 0;
      continue;
    }
    while (left > 0 && untouched(left - 1))
      --left;
    while (right < kWidth - 1 && untouched(right + 1))
      ++right;
    const double gap = right - left + 1;
    const double far_depth = 0.1 + 0.5 * 1.4 * grasper.shaft_radius;
    const double expected = 2 * std::tan(0.5 * angle) * below / far_depth * focal;
    EXPECT_NEAR(gap, expected, 2.0) << "angle " << angle;
    EXPECT_GT(gap, last_gap);
    last_gap = gap;
  }
}

// The flat tissue square facing a scope straight above it: at the middle pixel, l = v = n, so the
// colour is albedo (ambient + r diffuse) + r specular with r = 1 / (1 + (d / falloff)^2): nearer
// is brighter by exactly that law.
TEST_F(EndoscopeViewTest, TheScopesLightFallsOffWithDistanceAsDocumented) {
  SceneRenderer renderer;
  const Framebuffer target(kWidth, kHeight);
  const Surface tissue =
      square_surface(0.01, 4, Eigen::Matrix3d::Identity(), Eigen::Vector3d::Zero());
  const SceneStyle& style = renderer.style();
  double last = 0;
  for (const double distance : {0.12, 0.08, 0.04}) {
    Camera camera;
    camera.eye = Eigen::Vector3d(0.0001, 0.0001, distance);  // off the grid's shared vertex
    camera.target = Eigen::Vector3d(0.0001, 0.0001, 0);
    camera.up = Eigen::Vector3d::UnitY();
    camera.headlight = true;
    camera.light_falloff_m = 0.06;
    renderer.render(target, camera, tissue.view(), std::span<const ToolView>{});
    const std::vector<std::uint8_t> rgb = target.read_rgb();
    const double d = distance / camera.light_falloff_m;
    const double reach = 1 / (1 + d * d);
    const Eigen::Vector3d expected =
        255.0 * (style.tissue.albedo.cast<double>() * (style.ambient + reach * style.diffuse) +
                 Eigen::Vector3d::Constant(reach * style.tissue.specular))
                    .cwiseMin(1.0);
    const test::Pixel middle = pixel_at(rgb, kWidth, kHeight / 2, kWidth / 2);
    EXPECT_LE(colour_error(middle, expected), 3.0) << "at " << distance << " m";
    EXPECT_GT(middle[1], last);
    last = middle[1];
    // No floor inside the body: the corners show the cavity.
    const test::Pixel corner = pixel_at(rgb, kWidth, 0, 0);
    if (distance > 0.1) {
      EXPECT_LE(colour_error(corner, 255.0 * style.cavity.cast<double>()), 2.0);
    }
  }
}

// Flags on the faces of the square's right half (x > 0): those pixels take the cut wall's look in
// closed form, the left half the capsule's; all-zero flags draw what no flags draw.
TEST_F(EndoscopeViewTest, CutWallsAreDrawnInTheInteriorColourAndOnlyThere) {
  SceneRenderer renderer;
  const Framebuffer target(kWidth, kHeight);
  Surface tissue =
      square_surface(0.02, 8, Eigen::Matrix3d::Identity(), Eigen::Vector3d(0, 0, 0.03));
  Camera camera;
  camera.eye = Eigen::Vector3d(0.0, -0.06, 0.12);
  camera.target = Eigen::Vector3d(0.0, 0.0, 0.03);
  camera.up = Eigen::Vector3d::UnitZ();
  camera.fov_y_deg = 40;
  renderer.render(target, camera, tissue.view(), std::span<const ToolView>{});
  const std::vector<std::uint8_t> plain = target.read_rgb();

  std::vector<std::uint8_t> flags(static_cast<std::size_t>(tissue.F.rows()), 0);
  TissueView view = tissue.view();
  view.cut_faces = &flags;
  renderer.render(target, camera, view, std::span<const ToolView>{});
  EXPECT_EQ(target.read_rgb(), plain);

  for (Eigen::Index f = 0; f < tissue.F.rows(); ++f) {
    double x = 0;
    for (int k = 0; k < 3; ++k)
      x += tissue.V(tissue.F(f, k), 0) / 3;
    flags[static_cast<std::size_t>(f)] = x > 0 ? 1 : 0;
  }
  renderer.render(target, camera, view, std::span<const ToolView>{});
  const std::vector<std::uint8_t> cut = target.read_rgb();
  const SceneStyle& style = renderer.style();
  for (const double x : {-0.012, 0.012}) {
    const Eigen::Vector3d p(x, 0.003, 0.03);
    const PixelPosition at = project(camera, kWidth, kHeight, p);
    const Eigen::Vector3d v = (camera.eye - p).normalized();
    const SurfaceLook& look = x > 0 ? style.cut_wall : style.tissue;
    const Eigen::Vector3d expected = test::shade(style, look, Eigen::Vector3d::UnitZ(), v);
    EXPECT_LE(colour_error(pixel_at(cut, kWidth, at.row, at.column), expected), 4.0) << x;
    EXPECT_EQ(difference(plain, cut, at) > 40.0, x > 0) << x;
  }

  flags.pop_back();
  EXPECT_THROW(renderer.render(target, camera, view, std::span<const ToolView>{}),
               std::invalid_argument);
}

// A probe's ball 2 cm above flat tissue, a scope 8 cm above looking down: the shadows' light is
// 2 cm below the eye in the image (towards -y), so the ball's shadow falls on the far side (+y),
// centred where the line from that light through the ball meets the tissue. There the tissue gets
// a quarter of the light, in closed form; on the side towards the light nothing changes.
TEST_F(EndoscopeViewTest, TheInstrumentsShadowFallsOnTheFarSideFromTheLight) {
  SceneRenderer renderer;
  const Framebuffer target(kWidth, kHeight);
  const Surface tissue =
      square_surface(0.03, 6, Eigen::Matrix3d::Identity(), Eigen::Vector3d::Zero());
  Camera camera;
  camera.eye = Eigen::Vector3d(0, 0, 0.08);
  camera.target = Eigen::Vector3d::Zero();
  camera.up = Eigen::Vector3d::UnitY();
  camera.headlight = true;
  ToolView probe;
  probe.tip = Eigen::Vector3d(0, 0, 0.02);
  probe.radius = 0.003;
  probe.shaft_length = 0;
  renderer.render(target, camera, tissue.view(), std::span<const ToolView>{});
  const std::vector<std::uint8_t> bare = target.read_rgb();
  renderer.render(target, camera, tissue.view(), std::span<const ToolView>(&probe, 1));
  const std::vector<std::uint8_t> shaded = target.read_rgb();

  const Eigen::Vector3d light =
      camera.eye - camera.shadow_light_offset_m * Eigen::Vector3d::UnitY();
  const double t = light.z() / (light.z() - probe.tip.z());
  const Eigen::Vector3d centre = light + t * (probe.tip - light);
  ASSERT_GT(centre.y(), 0.005);  // beyond the ball's own image (3 mm at 6 cm from the eye)
  const SceneStyle& style = renderer.style();
  for (const double dy : {-0.001, 0.0, 0.001}) {
    const Eigen::Vector3d p = centre + Eigen::Vector3d(0, dy + 0.002, 0);
    const Eigen::Vector3d v = (camera.eye - p).normalized();
    const double distance = (camera.eye - p).norm() / camera.light_falloff_m;
    const double reach = 0.25 / (1 + distance * distance);
    const double highlight = std::pow(v.z(), style.tissue.shininess);
    const Eigen::Vector3d expected =
        255.0 *
        (style.tissue.albedo.cast<double>() * (style.ambient + reach * style.diffuse * v.z()) +
         Eigen::Vector3d::Constant(reach * style.tissue.specular * highlight));
    const PixelPosition at = project(camera, kWidth, kHeight, p);
    EXPECT_LE(colour_error(pixel_at(shaded, kWidth, at.row, at.column), expected), 3.0) << dy;
    EXPECT_GT(difference(bare, shaded, at), 20.0) << dy;
    // The mirror point, towards the light: untouched.
    const Eigen::Vector3d mirror(p.x(), -p.y(), p.z());
    EXPECT_LE(difference(bare, shaded, project(camera, kWidth, kHeight, mirror)), 1.0) << dy;
  }
}

TEST_F(EndoscopeViewTest, RejectsInstrumentsItCannotDraw) {
  SceneRenderer renderer;
  const Framebuffer target(64, 48);
  const Camera camera = side_scope();
  ToolView grasper;
  grasper.shape = ToolShape::grasper;
  grasper.side = grasper.shaft_direction;  // along the shaft: no opening plane
  EXPECT_THROW(draw(renderer, target, camera, {&grasper, 1}), std::invalid_argument);
  grasper.side = Eigen::Vector3d::UnitX();
  grasper.jaw_angle = std::numbers::pi;
  EXPECT_THROW(draw(renderer, target, camera, {&grasper, 1}), std::invalid_argument);
  ToolView scalpel;
  scalpel.shape = ToolShape::scalpel;
  scalpel.blade_length = 0;
  EXPECT_THROW(draw(renderer, target, camera, {&scalpel, 1}), std::invalid_argument);
  Camera dark = camera;
  dark.light_falloff_m = 0;
  EXPECT_THROW(draw(renderer, target, dark, {}), std::invalid_argument);
}

// A static surface (a bone) is drawn in its own look where it projects, with no tissue at all; a
// cavity's wall (inside_only) shows through the scope and not from outside; the surfaces stay
// until replaced, and a rejected set keeps them.
TEST_F(EndoscopeViewTest, SurroundingsAreDrawnInTheirLookAndTheCavityWallOnlyInside) {
  SceneStyle style;
  style.bone.albedo = Eigen::Vector3f(0.9f, 0.9f, 0.2f);
  style.lining.albedo = Eigen::Vector3f(0.2f, 0.3f, 0.9f);
  SceneRenderer renderer(style);
  const Framebuffer target(kWidth, kHeight);
  // Facing the camera (normal -y), 10 cm in front of it.
  Eigen::Matrix3d facing;
  facing << 1, 0, 0, 0, 0, -1, 0, 1, 0;
  const Surface bone = square_surface(0.01, 2, facing, Eigen::Vector3d(-0.012, 0, 0.035));
  const Surface wall = square_surface(0.01, 2, facing, Eigen::Vector3d(0.012, 0, 0.035));
  const std::vector<StaticSurface> surfaces = {{&bone.V, &bone.F, style.bone, false},
                                               {&wall.V, &wall.F, style.lining, true}};
  renderer.set_surroundings(surfaces);
  const Eigen::Vector3d on_bone(-0.012, 0, 0.035), on_wall(0.012, 0, 0.035);

  const Camera scope = side_scope();
  const std::vector<std::uint8_t> inside = draw(renderer, target, scope, {});
  for (const auto& [p, look] : {std::pair{on_bone, style.bone}, std::pair{on_wall, style.lining}}) {
    // Under the headlight l = v: n.l is the cosine to the eye, and so is n.h.
    const double d = (scope.eye - p).norm() / scope.light_falloff_m;
    const double reach = 1 / (1 + d * d);
    const double lambert = (scope.eye - p).normalized().dot(-Eigen::Vector3d::UnitY());
    const Eigen::Vector3d expected =
        255.0 *
        (look.albedo.cast<double>() * (style.ambient + reach * style.diffuse * lambert) +
         Eigen::Vector3d::Constant(reach * look.specular * std::pow(lambert, look.shininess)))
            .cwiseMin(1.0);
    const PixelPosition at = project(scope, kWidth, kHeight, p);
    EXPECT_LE(colour_error(pixel_at(inside, kWidth, at.row, at.column), expected), 4.0);
  }
  // Between the two squares: the cavity.
  const PixelPosition gap = project(scope, kWidth, kHeight, Eigen::Vector3d(0, 0, 0.035));
  EXPECT_LE(colour_error(pixel_at(inside, kWidth, gap.row, gap.column),
                         255.0 * style.cavity.cast<double>()),
            2.0);

  Camera outside = scope;
  outside.headlight = false;
  const std::vector<std::uint8_t> seen = draw(renderer, target, outside, {});
  const PixelPosition at_bone = project(outside, kWidth, kHeight, on_bone);
  const PixelPosition at_wall = project(outside, kWidth, kHeight, on_wall);
  const test::Pixel bone_pixel = pixel_at(seen, kWidth, at_bone.row, at_bone.column);
  EXPECT_GT(bone_pixel[0], 100);  // yellow: red and green high, blue low
  EXPECT_LT(bone_pixel[2], bone_pixel[0] / 2);
  const test::Pixel behind = pixel_at(seen, kWidth, at_wall.row, at_wall.column);
  EXPECT_LT(behind[2], 150);  // the backdrop's grey, not the wall's blue
  EXPECT_LE(std::abs(behind[2] - behind[0]), 40);

  Surface broken = bone;
  broken.F(0, 0) = 99;
  const std::vector<StaticSurface> bad = {{&broken.V, &broken.F, style.bone, false}};
  EXPECT_THROW(renderer.set_surroundings(bad), std::invalid_argument);
  EXPECT_EQ(draw(renderer, target, scope, {}), inside);
  renderer.set_surroundings({});
  EXPECT_NE(draw(renderer, target, scope, {}), inside);
}

// From outside, the floor lies under the surroundings too, not only under the tissue: a bone lower
// than the tissue shows in its own look, in closed form, instead of being buried in the floor.
TEST_F(EndoscopeViewTest, TheFloorLiesUnderTheSurroundingsSeenFromOutside) {
  SceneRenderer renderer;
  const Framebuffer target(kWidth, kHeight);
  const Surface tissue =
      square_surface(0.01, 4, Eigen::Matrix3d::Identity(), Eigen::Vector3d(0, 0, 0.03));
  const Surface bone =
      square_surface(0.01, 4, Eigen::Matrix3d::Identity(), Eigen::Vector3d(0.03, 0, 0.0));
  const SceneStyle& style = renderer.style();
  const std::vector<StaticSurface> surfaces = {{&bone.V, &bone.F, style.bone, false}};
  renderer.set_surroundings(surfaces);
  Camera camera;
  camera.eye = Eigen::Vector3d(0.015, -0.06, 0.12);
  camera.target = Eigen::Vector3d(0.015, 0, 0.01);
  camera.up = Eigen::Vector3d::UnitZ();
  camera.fov_y_deg = 40;
  renderer.render(target, camera, tissue.view(), std::span<const ToolView>{});
  const std::vector<std::uint8_t> rgb = target.read_rgb();
  const Eigen::Vector3d p(0.03, 0.003, 0.0);
  const PixelPosition at = project(camera, kWidth, kHeight, p);
  const Eigen::Vector3d expected =
      test::shade(style, style.bone, Eigen::Vector3d::UnitZ(), (camera.eye - p).normalized());
  EXPECT_LE(colour_error(pixel_at(rgb, kWidth, at.row, at.column), expected), 4.0);
}

}  // namespace
}  // namespace incise::render
