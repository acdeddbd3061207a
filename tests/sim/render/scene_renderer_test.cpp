#include "sim/render/scene_renderer.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <numbers>
#include <stdexcept>

#include "gl_test.h"
#include "scene_test_util.h"

namespace incise::render {
namespace {

using test::colour_error;
using test::pixel_at;
using test::PixelPosition;
using test::project;
using test::shade;
using test::square_surface;
using test::Surface;

using SceneRendererTest = GlTest;

// A 4 cm tissue square at z = 0.03, seen obliquely from above and in front (the live view's
// usual angle).
Surface flat_tissue() {
  return square_surface(0.02, 8, Eigen::Matrix3d::Identity(), Eigen::Vector3d(0, 0, 0.03));
}

Camera oblique_camera() {
  Camera camera;
  camera.eye = Eigen::Vector3d(0.0, -0.12, 0.13);
  camera.target = Eigen::Vector3d(0.0, 0.0, 0.03);
  camera.up = Eigen::Vector3d::UnitZ();
  camera.fov_y_deg = 40.0;
  return camera;
}

ToolView tool_at(const Eigen::Vector3d& tip) {
  ToolView tool;
  tool.tip = tip;
  tool.shaft_direction = Eigen::Vector3d(0.2, 0.3, 1.0);
  return tool;
}

// The colour of the tool sphere at the pixel that holds the tip's projection: the closed-form
// shading of the exact sphere where the pixel's central ray meets it.
Eigen::Vector3d tip_pixel_colour(const SceneStyle& style, const SurfaceLook& look,
                                 const Camera& camera, int width, int height,
                                 const ToolView& tool) {
  const PixelPosition tip = project(camera, width, height, tool.tip);
  const Eigen::Vector3d ray = test::pixel_ray(camera, width, height, tip.row, tip.column);
  // |eye + t ray - tip| = radius, nearer root.
  const Eigen::Vector3d offset = camera.eye - tool.tip;
  const double b = ray.dot(offset);
  const double c = offset.squaredNorm() - tool.radius * tool.radius;
  const double t = -b - std::sqrt(b * b - c);
  const Eigen::Vector3d hit = camera.eye + t * ray;
  return shade(style, look, (hit - tool.tip).normalized(), -ray);
}

std::vector<std::uint8_t> draw(SceneRenderer& renderer, const Framebuffer& target,
                               const Camera& camera, const TissueView& tissue,
                               const ToolView& tool) {
  renderer.render(target, camera, tissue, tool);
  return target.read_rgb();
}

TEST_F(SceneRendererTest, ToolSphereAppearsWhereTheCameraProjectsItsTip) {
  SceneRenderer renderer;
  const Framebuffer target(320, 240);
  const Camera camera = oblique_camera();
  const Surface tissue = flat_tissue();
  const ToolView tool = tool_at(Eigen::Vector3d(0.012, 0.004, 0.045));
  const std::vector<std::uint8_t> rgb = draw(renderer, target, camera, tissue.view(), tool);

  const Eigen::Vector3d expected =
      tip_pixel_colour(renderer.style(), renderer.style().tool, camera, 320, 240, tool);
  const PixelPosition tip = project(camera, 320, 240, tool.tip);
  EXPECT_LE(colour_error(pixel_at(rgb, 320, tip.row, tip.column), expected), 4.0);
  // The same distance to the left of the image centre: tissue, not tool.
  const PixelPosition mirror{tip.row, 320 - tip.column};
  EXPECT_GT(colour_error(pixel_at(rgb, 320, mirror.row, mirror.column), expected), 40.0);
  // A corner of the image: floor, not tool.
  EXPECT_GT(colour_error(pixel_at(rgb, 320, 239, 0), expected), 40.0);
}

TEST_F(SceneRendererTest, InContactDrawsTheToolInTheHighlightColour) {
  SceneRenderer renderer;
  const Framebuffer target(160, 120);
  const Camera camera = oblique_camera();
  const Surface tissue = flat_tissue();
  ToolView tool = tool_at(Eigen::Vector3d(0.0, 0.0, 0.035));
  const PixelPosition tip = project(camera, 160, 120, tool.tip);

  const test::Pixel free =
      pixel_at(draw(renderer, target, camera, tissue.view(), tool), 160, tip.row, tip.column);
  tool.in_contact = true;
  const test::Pixel contact =
      pixel_at(draw(renderer, target, camera, tissue.view(), tool), 160, tip.row, tip.column);

  const SceneStyle& style = renderer.style();
  EXPECT_LE(colour_error(free, tip_pixel_colour(style, style.tool, camera, 160, 120, tool)), 4.0);
  EXPECT_LE(
      colour_error(contact, tip_pixel_colour(style, style.tool_in_contact, camera, 160, 120, tool)),
      4.0);
  EXPECT_GT(colour_error(contact, Eigen::Vector3d(free[0], free[1], free[2])), 40.0);
}

// A mark (an ink dot of a marked line) is a sphere in the marker's look, shaded like the tool's
// sphere; invalid marks are refused before anything is drawn.
TEST_F(SceneRendererTest, MarksAreDrawnInTheMarkerColourWhereTheyProject) {
  SceneRenderer renderer;
  const Framebuffer target(320, 240);
  const Camera camera = oblique_camera();
  const Surface tissue = flat_tissue();
  const ToolView tool = tool_at(Eigen::Vector3d(0.012, 0.004, 0.045));
  const MarkView mark{Eigen::Vector3d(-0.006, 0.002, 0.031), 0.002};
  renderer.render(target, camera, tissue.view(), std::span<const ToolView>(&tool, 1),
                  std::span<const MarkView>(&mark, 1));
  const std::vector<std::uint8_t> rgb = target.read_rgb();
  ToolView as_sphere;
  as_sphere.tip = mark.centre;
  as_sphere.radius = mark.radius;
  const SceneStyle& style = renderer.style();
  const Eigen::Vector3d expected =
      tip_pixel_colour(style, style.marker, camera, 320, 240, as_sphere);
  const PixelPosition at = project(camera, 320, 240, mark.centre);
  EXPECT_LE(colour_error(pixel_at(rgb, 320, at.row, at.column), expected), 4.0);
  // Without the mark the same pixel is tissue.
  const std::vector<std::uint8_t> plain = draw(renderer, target, camera, tissue.view(), tool);
  EXPECT_GT(colour_error(pixel_at(plain, 320, at.row, at.column), expected), 40.0);

  for (const MarkView& bad :
       {MarkView{mark.centre, 0.0}, MarkView{Eigen::Vector3d(0, std::nan(""), 0), 0.001}}) {
    EXPECT_THROW(renderer.render(target, camera, tissue.view(), std::span<const ToolView>(&tool, 1),
                                 std::span<const MarkView>(&bad, 1)),
                 std::invalid_argument);
  }
}

// Screen rectangle [row0, row1] x [column0, column1] that holds the tool's whole image: the
// projections of the corners of a world box around sphere and shaft, widened by two pixels.
struct ScreenBox {
  int row0, row1, column0, column1;
  bool contains(int row, int column) const {
    return row >= row0 && row <= row1 && column >= column0 && column <= column1;
  }
};

// With a light, the box also holds the tool's shadow on the plane z = plane_z: the tool's box
// corners projected from the light onto that plane.
ScreenBox tool_screen_box(const Camera& camera, int width, int height, const ToolView& tool,
                          const Eigen::Vector3d* light = nullptr, double plane_z = 0) {
  const Eigen::Vector3d end = tool.tip + tool.shaft_length * tool.shaft_direction.normalized();
  const double reach = std::max(tool.radius, tool.shaft_radius);
  Eigen::Vector3d low = tool.tip.cwiseMin(end).array() - reach;
  Eigen::Vector3d high = tool.tip.cwiseMax(end).array() + reach;
  if (light != nullptr) {
    const Eigen::Vector3d l0 = low, h0 = high;
    for (int corner = 0; corner < 8; ++corner) {
      const Eigen::Vector3d p(corner & 1 ? h0.x() : l0.x(), corner & 2 ? h0.y() : l0.y(),
                              corner & 4 ? h0.z() : l0.z());
      const double t = (light->z() - plane_z) / (light->z() - p.z());
      const Eigen::Vector3d shadow = *light + t * (p - *light);
      low = low.cwiseMin(shadow);
      high = high.cwiseMax(shadow);
    }
  }
  ScreenBox box{height, -1, width, -1};
  for (int corner = 0; corner < 8; ++corner) {
    const Eigen::Vector3d p(corner & 1 ? high.x() : low.x(), corner & 2 ? high.y() : low.y(),
                            corner & 4 ? high.z() : low.z());
    const PixelPosition q = project(camera, width, height, p);
    box = {std::min(box.row0, q.row - 2), std::max(box.row1, q.row + 2),
           std::min(box.column0, q.column - 2), std::max(box.column1, q.column + 2)};
  }
  return box;
}

// Only the tool and its shadow change.
TEST_F(SceneRendererTest, MovingTheToolChangesTheImageOnlyNearTheTool) {
  SceneRenderer renderer;
  const int width = 200;
  const int height = 150;
  const Framebuffer target(width, height);
  const Camera camera = oblique_camera();
  const Surface tissue = flat_tissue();
  ToolView before = tool_at(Eigen::Vector3d(-0.01, 0.0, 0.04));
  before.shaft_length = 0.03;  // short, so that the boxes leave most of the image outside
  ToolView after = before;
  after.tip = Eigen::Vector3d(0.012, -0.006, 0.036);

  const std::vector<std::uint8_t> a = draw(renderer, target, camera, tissue.view(), before);
  const std::vector<std::uint8_t> b = draw(renderer, target, camera, tissue.view(), after);
  // The tool's shadow moves with it (the directional light, 10 m from the tissue's centre).
  const Eigen::Vector3d light =
      Eigen::Vector3d(0, 0, 0.03) + 10.0 * renderer.style().to_light.normalized();
  const ScreenBox box_before = tool_screen_box(camera, width, height, before, &light, 0.03);
  const ScreenBox box_after = tool_screen_box(camera, width, height, after, &light, 0.03);

  int changed = 0;
  int outside = 0;
  for (int row = 0; row < height; ++row) {
    for (int column = 0; column < width; ++column) {
      if (pixel_at(a, width, row, column) == pixel_at(b, width, row, column)) continue;
      ++changed;
      if (!box_before.contains(row, column) && !box_after.contains(row, column)) {
        ADD_FAILURE() << "pixel far from the tool changed: row " << row << " column " << column;
        if (++outside > 5) return;
      }
    }
  }
  // Both tip discs at least changed (the sphere covers tens of pixels here).
  EXPECT_GT(changed, 100);
  const PixelPosition tip_before = project(camera, width, height, before.tip);
  const PixelPosition tip_after = project(camera, width, height, after.tip);
  EXPECT_NE(pixel_at(a, width, tip_before.row, tip_before.column),
            pixel_at(b, width, tip_before.row, tip_before.column));
  EXPECT_NE(pixel_at(a, width, tip_after.row, tip_after.column),
            pixel_at(b, width, tip_after.row, tip_after.column));
}

// The same tilted square twice, its normal tipped towards the light and then away from it,
// seen from straight above: Lambert's law makes the first brighter, by the closed-form amount.
TEST_F(SceneRendererTest, TissueFacingTheLightIsBrighterThanTurnedAway) {
  SceneRenderer renderer;
  const Framebuffer target(64, 64);
  Camera camera;
  camera.eye = Eigen::Vector3d(0, 0, 0.3);
  camera.target = Eigen::Vector3d::Zero();
  camera.up = Eigen::Vector3d::UnitY();
  ToolView tool = tool_at(Eigen::Vector3d(0.0, 0.0, 1.0));  // out of sight
  const SceneStyle& style = renderer.style();
  // Tilting about x moves the normal in the y-z plane; the light's y component decides which
  // way is towards it.
  const double towards = style.to_light.y() < 0 ? 1.0 : -1.0;
  const double angle = std::numbers::pi / 3;

  std::array<int, 2> brightness{};
  for (int k = 0; k < 2; ++k) {
    const double tilt = (k == 0 ? towards : -towards) * angle;
    const Eigen::Matrix3d rotation = Eigen::AngleAxisd(tilt, Eigen::Vector3d::UnitX()).matrix();
    const Surface tissue = square_surface(0.03, 2, rotation, Eigen::Vector3d::Zero());
    const test::Pixel centre =
        pixel_at(draw(renderer, target, camera, tissue.view(), tool), 64, 32, 32);
    const Eigen::Vector3d n = rotation * Eigen::Vector3d::UnitZ();
    const Eigen::Vector3d v = Eigen::Vector3d::UnitZ();  // centre of the square to the eye
    EXPECT_LE(colour_error(centre, shade(style, style.tissue, n, v)), 2.0) << "tilt " << tilt;
    brightness[k] = centre[0] + centre[1] + centre[2];
  }
  EXPECT_GT(brightness[0], brightness[1] + 60);
}

// Normals pointing away from the camera are turned round: a surface looks the same from either
// side, as cut tissue must.
TEST_F(SceneRendererTest, BothSidesOfTheTissueAreLitAlike) {
  SceneRenderer renderer;
  const Framebuffer target(48, 48);
  const Camera camera = oblique_camera();
  const ToolView tool = tool_at(Eigen::Vector3d(0.0, 0.0, 1.0));
  Surface front = flat_tissue();
  Surface back = front;
  back.N = -front.N;
  back.F.col(1).swap(back.F.col(2));  // reversed winding too
  EXPECT_EQ(draw(renderer, target, camera, front.view(), tool),
            draw(renderer, target, camera, back.view(), tool));
}

// Looking horizontally from the height of the tissue's lowest point, the floor (floor_gap below
// that point) fills the image just below the centre row and the backdrop just above it. A floor
// 5 mm lower would leave the row below the centre to the backdrop (its horizon would sit below).
TEST_F(SceneRendererTest, FloorLiesJustBelowTheTissuesLowestPoint) {
  SceneRenderer renderer;
  const int width = 320;
  const int height = 240;
  const Framebuffer target(width, height);
  // Tilted about x, so that the lowest point is one edge rather than the centre.
  const Eigen::Matrix3d rotation = Eigen::AngleAxisd(0.4, Eigen::Vector3d::UnitX()).matrix();
  const Surface tissue = square_surface(0.02, 4, rotation, Eigen::Vector3d(0.01, 0.02, 0.05));
  const double lowest = tissue.V.col(2).minCoeff();
  Camera camera;
  camera.eye = Eigen::Vector3d(0.01, -0.3, lowest);
  camera.target = Eigen::Vector3d(0.01, 0.0, lowest);
  camera.up = Eigen::Vector3d::UnitZ();
  const ToolView tool = tool_at(Eigen::Vector3d(0.0, 0.0, 1.0));  // out of sight
  const std::vector<std::uint8_t> rgb = draw(renderer, target, camera, tissue.view(), tool);

  const SceneStyle& style = renderer.style();
  const Eigen::Vector3d floor_colour =
      shade(style, style.floor, Eigen::Vector3d::UnitZ(), Eigen::Vector3d::UnitZ());
  const auto backdrop_colour = [&](int row) {
    const double height_fraction = 1.0 - (row + 0.5) / height;
    return 255.0 * (style.backdrop_bottom.cast<double>() +
                    height_fraction * (style.backdrop_top - style.backdrop_bottom).cast<double>());
  };
  // Columns well beside the tissue, whose image spans about 40 pixels either side of the centre.
  for (const int column : {10, 60, width - 60, width - 10}) {
    EXPECT_LE(colour_error(pixel_at(rgb, width, height / 2 + 1, column), floor_colour), 2.0)
        << "column " << column;
    // Further down, but not so far that the floor comes nearer than the near clip plane.
    EXPECT_LE(colour_error(pixel_at(rgb, width, height / 2 + 20, column), floor_colour), 2.0);
    EXPECT_LE(
        colour_error(pixel_at(rgb, width, height / 2 - 2, column), backdrop_colour(height / 2 - 2)),
        2.0)
        << "column " << column;
    EXPECT_LE(colour_error(pixel_at(rgb, width, 0, column), backdrop_colour(0)), 2.0);
  }
  // The tissue itself rises above the centre row in the middle.
  EXPECT_LE(colour_error(pixel_at(rgb, width, height / 2 - 4, width / 2),
                         shade(style, style.tissue, rotation * Eigen::Vector3d::UnitZ(),
                               (camera.eye - tissue.V.row(0).transpose()).normalized())),
            12.0);
}

// The faces are uploaded only when they differ from the last frame's, so a change of faces with
// the same count, a change of vertex count and a change back must all show.
TEST_F(SceneRendererTest, ChangedTopologyIsRedrawnLikeAFreshRenderer) {
  const Framebuffer target(64, 48);
  const Camera camera = oblique_camera();
  const ToolView tool = tool_at(Eigen::Vector3d(0.0, 0.0, 1.0));
  const Surface coarse =
      square_surface(0.02, 2, Eigen::Matrix3d::Identity(), Eigen::Vector3d(0, 0, 0.03));
  Surface half = coarse;  // same counts, every face replaced by the first one
  half.F.rowwise() = coarse.F.row(0);
  const Surface fine = flat_tissue();

  const auto fresh = [&](const Surface& surface) {
    SceneRenderer renderer;
    return draw(renderer, target, camera, surface.view(), tool);
  };
  SceneRenderer renderer;
  for (const Surface* surface :
       std::initializer_list<const Surface*>{&coarse, &half, &fine, &coarse}) {
    EXPECT_EQ(draw(renderer, target, camera, surface->view(), tool), fresh(*surface));
  }
  EXPECT_NE(fresh(coarse), fresh(half));
}

TEST_F(SceneRendererTest, RejectsInvalidInputBeforeDrawing) {
  SceneRenderer renderer;
  const Framebuffer target(8, 8);
  const Camera camera = oblique_camera();
  const Surface tissue = flat_tissue();
  const ToolView tool = tool_at(Eigen::Vector3d(0, 0, 0.05));
  const std::vector<std::uint8_t> good = draw(renderer, target, camera, tissue.view(), tool);

  TissueView partial = tissue.view();
  partial.N = nullptr;
  EXPECT_THROW(renderer.render(target, camera, partial, tool), std::invalid_argument);
  Surface short_normals = tissue;
  short_normals.N.conservativeResize(3, 3);
  EXPECT_THROW(renderer.render(target, camera, short_normals.view(), tool), std::invalid_argument);
  Surface bad_index = tissue;
  bad_index.F(5, 1) = static_cast<int>(tissue.V.rows());
  try {
    renderer.render(target, camera, bad_index.view(), tool);
    ADD_FAILURE() << "an out-of-range face index was accepted";
  } catch (const std::invalid_argument& error) {
    EXPECT_STREQ(error.what(), "tissue face 5 has vertex index 81 outside [0, 81)");
  }
  Surface not_finite = tissue;
  not_finite.V(7, 2) = std::numeric_limits<double>::quiet_NaN();
  EXPECT_THROW(renderer.render(target, camera, not_finite.view(), tool), std::invalid_argument);

  for (const auto& change :
       {+[](ToolView& t) { t.radius = 0; }, +[](ToolView& t) { t.shaft_radius = -1; },
        +[](ToolView& t) { t.shaft_length = -0.1; },
        +[](ToolView& t) { t.shaft_direction.setZero(); },
        +[](ToolView& t) { t.tip.x() = std::numeric_limits<double>::infinity(); }}) {
    ToolView bad = tool;
    change(bad);
    EXPECT_THROW(renderer.render(target, camera, tissue.view(), bad), std::invalid_argument);
  }
  Camera degenerate = camera;
  degenerate.target = degenerate.eye;
  EXPECT_THROW(renderer.render(target, degenerate, tissue.view(), tool), std::invalid_argument);

  // Rejected frames leave the renderer as it was: the good frame draws as before.
  EXPECT_EQ(draw(renderer, target, camera, tissue.view(), tool), good);
}

TEST_F(SceneRendererTest, RejectsInvalidStyles) {
  SceneStyle style;
  style.to_light.setZero();
  EXPECT_THROW(SceneRenderer{style}, std::invalid_argument);
  style = SceneStyle();
  style.floor_half_size = 0;
  EXPECT_THROW(SceneRenderer{style}, std::invalid_argument);
  style = SceneStyle();
  style.tool.shininess = 0;
  EXPECT_THROW(SceneRenderer{style}, std::invalid_argument);
  style = SceneStyle();
  style.marker.shininess = -1;
  EXPECT_THROW(SceneRenderer{style}, std::invalid_argument);
  style = SceneStyle();
  style.up = Eigen::Vector3d(0, 0, 3);
  EXPECT_TRUE(SceneRenderer(style).style().up.isApprox(Eigen::Vector3d::UnitZ()));
}

}  // namespace
}  // namespace incise::render
