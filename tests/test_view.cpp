// The camera of `wavepath view` without a window: the course's orbit, pan
// and zoom arithmetic, the scene's view kept exactly until the user moves
// it, and the camera file read back by `render -c` giving the same camera.
// The window itself is tested under Xvfb (view_cli.sh).
#include "test_support.h"

#include "scene/importers.h"
#include "view/accumulation.h"
#include "view/view_camera.h"

namespace wp::test {
namespace {

constexpr double kPi = 3.14159265358979323846;

Scene cornell() { return load_scene(source_path("scenes/cornell-box.json")); }

void expect_same_camera(const Camera& a, const Camera& b, const char* what) {
  for (int c = 0; c < 4; ++c)
    for (int r = 0; r < 4; ++r) EXPECT_EQ(a.toWorld[c][r], b.toWorld[c][r]) << what << ", toWorld[" << c << "][" << r << "]";
  EXPECT_EQ(a.vfovDegrees, b.vfovDegrees) << what;
  // The aspect as the kernels see it (0 stands for width / height).
  auto aspect = [](const Camera& c) { return c.aspect > 0.0f ? c.aspect : float(c.width) / float(c.height); };
  EXPECT_EQ(aspect(a), aspect(b)) << what;
  EXPECT_EQ(a.apertureRadius, b.apertureRadius) << what;
  EXPECT_EQ(a.focusDistance, b.focusDistance) << what;
}

TEST(ViewCamera, AnUnmovedViewIsTheScenesCameraExactly) {
  for (const char* path : {"scenes/cornell-box.json", "tests/data/gltf/layers.glb", "tests/data/collada/cornell.dae"}) {
    Scene s = load_scene(source_path(path));
    ViewCamera v(s.camera, scene_bounds(s));
    expect_same_camera(v.camera(), s.camera, path);
    v.orbit(40, -25, 800, 600);
    v.reset();
    expect_same_camera(v.camera(), s.camera, path);
  }
}

TEST(ViewCamera, OrbitTurnsAboutTheTargetAsTheCourseDoes) {
  Scene s = cornell();
  ViewCamera v(s.camera, scene_bounds(s));
  const glm::dvec3 target = v.target();
  const double r = v.distance();
  // A drag the window's full width turns theta by pi: two return the camera.
  v.orbit(400, 0, 400, 300);
  EXPECT_NEAR(glm::length(v.position() - target), r, 1e-9 * r);
  v.orbit(400, 0, 400, 300);
  EXPECT_NEAR(glm::length(v.position() - (target + (glm::dvec3(s.camera.toWorld[3]) - target))), 0.0, 1e-6 * r);
  // A drag up half the height raises the camera by pi/2 of polar angle,
  // clamped at the pole; it keeps looking at the target.
  const double phi0 = std::acos(glm::dot(glm::normalize(v.position() - target), v.up_axis()));
  v.orbit(0, -150, 400, 300);
  const double phi1 = std::acos(glm::clamp(glm::dot(glm::normalize(v.position() - target), v.up_axis()), -1.0, 1.0));
  EXPECT_NEAR(phi1, std::min(phi0 + kPi / 2, kPi - 1e-5), 1e-6);
  EXPECT_NEAR(glm::length(glm::normalize(v.position() - target) - glm::normalize(v.orientation()[2])), 0.0, 1e-9);
  // The course's compute_position, with phi and theta from the settings file.
  std::vector<double> f = v.settings();
  const double phi = f[11], theta = f[12], rr = f[13];
  const glm::dvec3 course = target + rr * glm::dvec3(std::sin(phi) * std::sin(theta), std::cos(phi), std::sin(phi) * std::cos(theta));
  EXPECT_NEAR(glm::length(course - v.position()), 0.0, 1e-9 * r) << "the Cornell box stands on +Y, as the course's scenes do";
}

TEST(ViewCamera, PanMovesAPointAtTheCanonicalDistanceWithTheCursor) {
  Scene s = cornell();
  ViewCamera v(s.camera, scene_bounds(s));
  const int H = 512;
  const glm::dvec3 p0 = v.position(), t0 = v.target(), right = glm::normalize(v.orientation()[0]);
  v.pan(-32, 0, H);  // cursor 32 pixels left: the camera moves right
  const double screenDistance = H / (2.0 * std::tan(glm::radians(double(s.camera.vfovDegrees)) / 2.0));
  EXPECT_NEAR(glm::dot(v.position() - p0, right), 32 * v.canonical_distance() / screenDistance, 1e-9);
  EXPECT_NEAR(glm::length((v.position() - p0) - (v.target() - t0)), 0.0, 1e-12) << "the target moves with the camera";
}

TEST(ViewCamera, TheWheelMovesByATenthOfTheCanonicalDistanceWithinTheCoursesLimits) {
  Scene s = cornell();
  ViewCamera v(s.camera, scene_bounds(s));
  const double r0 = v.distance(), c = v.canonical_distance();
  v.zoom(1);  // wheel up: away, as in the course
  EXPECT_NEAR(v.distance(), r0 + c / 10, 1e-9 * r0);
  v.zoom(-2);
  EXPECT_NEAR(v.distance(), r0 - c / 10, 1e-9 * r0);
  v.zoom(-1000);
  EXPECT_NEAR(v.distance(), std::min(c / 10, r0), 1e-9 * r0);
  v.zoom(1e6);
  EXPECT_NEAR(v.distance(), std::max(c * 20, r0), 1e-9 * r0);
}

TEST(ViewCamera, TheCameraFileGivesRenderMinusCTheWindowsCamera) {
  Scene s = cornell();
  ViewCamera v(s.camera, scene_bounds(s));
  v.orbit(-70, 33, 512, 512);
  v.pan(12, -5, 512);
  v.zoom(-1.5);
  v.fly(glm::dvec3(0.1, 0, -0.2));
  v.change_aperture(0.05);
  const std::string path = (std::filesystem::temp_directory_path() / ("wavepath-view-camera-" + std::to_string(getpid()) + ".txt")).string();
  {
    std::ofstream out(path);
    out << v.settings_text();
  }
  const std::vector<double> read = read_cs184_camera_settings(path);
  ASSERT_EQ(read, v.settings()) << "every number is written with the digits that read it back";
  Camera fromFile = s.camera;
  apply_cs184_camera_settings(path, fromFile);
  fromFile.apertureRadius = float(read[29]);  // render takes the lens from -b / -d, as the course does
  fromFile.focusDistance = float(read[28]);
  expect_same_camera(fromFile, v.camera(), "read back");
  std::remove(path.c_str());
  // The lens never goes below zero (the course's K and ; floors).
  for (int i = 0; i < 10; ++i) v.change_aperture(-0.05);
  EXPECT_EQ(v.camera().apertureRadius, 0.0f);
}

// A planted error: the course's file stores c2w row by row; one read as
// columns would turn the camera.
TEST(ViewCamera, ATransposedOrientationIsCaught) {
  Scene s = cornell();
  ViewCamera v(s.camera, scene_bounds(s));
  v.orbit(-70, 33, 512, 512);
  std::vector<double> f = v.settings();
  for (int i = 0; i < 3; ++i)
    for (int j = i + 1; j < 3; ++j) std::swap(f[size_t(16 + 3 * i + j)], f[size_t(16 + 3 * j + i)]);
  Camera transposed = s.camera;
  apply_cs184_camera_settings(f, transposed, "planted");
  EXPECT_GT(glm::length(glm::vec3(transposed.toWorld[2]) - glm::vec3(v.camera().toWorld[2])), 0.1f);
}

// The window's image through the changes the user makes.
TEST(ViewAccumulation, MoreSamplesContinueFewerOrAnyChangeOfStrataStartAgain) {
  ViewAccumulation a(8, false);
  EXPECT_EQ(a.todo().begin, 0u);
  a.reach(5);
  EXPECT_FALSE(a.set_target(16)) << "] continues the image";
  EXPECT_EQ(a.reached(), 5u);
  EXPECT_EQ(a.todo().begin, 5u);
  EXPECT_EQ(a.todo().end, 16u);
  a.reach(16);
  EXPECT_TRUE(a.done());
  EXPECT_TRUE(a.set_target(8)) << "[ below what the image holds starts it again";
  EXPECT_EQ(a.reached(), 0u);
  a.reach(4);
  EXPECT_FALSE(a.set_target(4)) << "a target the image has reached keeps it";
  EXPECT_TRUE(a.done());
  a.restart();
  EXPECT_EQ(a.reached(), 0u);
  EXPECT_FALSE(a.done());
  a.reach(100);
  EXPECT_EQ(a.reached(), 4u) << "never past the target";
  ViewAccumulation cmj(8, true);
  cmj.reach(3);
  EXPECT_TRUE(cmj.set_target(16)) << "CMJ's strata depend on the count";
  EXPECT_EQ(cmj.reached(), 0u);
  EXPECT_FALSE(cmj.set_target(16));
  EXPECT_EQ(ViewAccumulation(0, false).target(), 1u);
}

}  // namespace
}  // namespace wp::test
