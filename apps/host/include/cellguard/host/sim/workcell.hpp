// SPDX-FileCopyrightText: 2026 The cellguard authors
// SPDX-License-Identifier: Apache-2.0
/// @file workcell.hpp
/// A simulated workcell in the paper's arrangement: a 4 m x 4 m x 2 m frame
/// (x and y in [-2, 2] m, floor at z = 0), one sensor in each upper corner
/// near the ceiling aimed at the centre, boxes on the floor and, optionally,
/// a robot as capsules (a RobotPose of lib/robot: every point within a
/// radius of a segment, solid and opaque like the boxes). Depth images are
/// ray cast exactly (ideal sensors); noise models are in noise.hpp, scene
/// files in scene_file.hpp, the ideal ground truth in ground_truth.hpp, the
/// robot's trajectory and the simulated PLC's schedule in trajectory.hpp.
#ifndef CELLGUARD_HOST_SIM_WORKCELL_HPP
#define CELLGUARD_HOST_SIM_WORKCELL_HPP

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "cellguard/grid/sensor_frame.hpp"
#include "cellguard/robot/kinematics.hpp"

namespace cellguard::sim {

/// A box standing in the cell, rotated about the vertical axis.
struct Box {
    Eigen::Vector3d center = Eigen::Vector3d::Zero();  ///< centre, metres
    Eigen::Vector3d size = Eigen::Vector3d::Ones();    ///< edge lengths along its own axes, metres
    double yaw = 0.0;                                  ///< rotation about +z, radians
    bool background = true;                            ///< part of the static background
};

/// What the sensors look at: the floor plane z = 0, boxes and the robot's
/// capsules (never background: the robot is absent from the empty cell).
struct Scene {
    std::vector<Box> boxes;  ///< the boxes
    bool floor = true;       ///< whether the floor plane reflects
    RobotPose robot{};       ///< the robot's capsules in the world frame; count 0: no robot (fixed capacity)
};

/// A depth sensor: where it is, where it looks, its image.
struct SensorSpec {
    std::string name;                                    ///< a label for reports
    Eigen::Vector3d position = Eigen::Vector3d::Zero();  ///< optical centre, workcell frame
    Eigen::Vector3d target = Eigen::Vector3d::Zero();    ///< point on the optical axis
    std::int32_t width = 0;                              ///< image columns
    std::int32_t height = 0;                             ///< image rows
    double hfov_deg = 0.0;                               ///< horizontal field of view, degrees
    double vfov_deg = 0.0;                               ///< vertical field of view, degrees
    float max_range = 10.0F;                             ///< readings beyond are dropped by fusion
    /// True: fx, fy, cx, cy below are the sensor's intrinsics (a calibrated
    /// camera, any principal point); false: they follow from the fields of
    /// view with the principal point in the image centre. Set by set_intrinsics.
    bool has_intrinsics = false;
    double fx = 0.0;  ///< has_intrinsics: focal length along columns, pixels
    double fy = 0.0;  ///< has_intrinsics: focal length along rows, pixels
    double cx = 0.0;  ///< has_intrinsics: principal point, column (pixel centres at integers)
    double cy = 0.0;  ///< has_intrinsics: principal point, row
    /// Sensor frame -> workcell frame (x right, y down, z along the optical axis).
    [[nodiscard]] Eigen::Isometry3d pose() const;
    /// Pinhole intrinsics: fx, fy, cx, cy as given (has_intrinsics), else
    /// from the fields of view with a centred principal point. Every image the
    /// simulator renders, and every reading and ray it makes, uses these.
    [[nodiscard]] PinholeIntrinsics intrinsics() const;
    /// Gives explicit intrinsics (after width and height): sets
    /// has_intrinsics and fx..cy, and hfov_deg / vfov_deg to the angles
    /// 2 atan(width / (2 fx)) and 2 atan(height / (2 fy)) (for reports; a
    /// principal point off centre makes the two halves of the view unequal).
    void set_intrinsics(double focal_x, double focal_y, double centre_x, double centre_y);
};

/// The paper's four sensors (BENCHMARKING.md's reference frame): two
/// 176 x 144 flash lidars (43.6 x 34.6 deg) and two 320 x 240 stereo
/// cameras (60 x 45 deg), one in each upper corner at (+-1.9, +-1.9, 1.9) m,
/// aimed at the centre of the floor; max range 10 m. Every pixel meets the
/// floor or a box: 204,288 rays a frame.
std::vector<SensorSpec> paper_sensors();

/// The reference scene: floor plus two boxes near the centre.
Scene reference_scene();

/// Ray casts @p scene into a depth image (z along the optical axis, metres;
/// 0 where nothing is hit within max_range). @p depth gets width * height values.
void render_depth(const SensorSpec& sensor, const Scene& scene, std::vector<float>& depth);

/// Distance along the ray origin + t * dir (dir unit length) to the first
/// surface of @p scene, or +infinity.
double cast_ray(const Scene& scene, const Eigen::Vector3d& origin, const Eigen::Vector3d& dir);

/// Distance along the ray origin + t * dir (dir unit length) to the surface
/// of the ball of radius @p r about @p c, 0 when the origin lies inside,
/// +infinity when the ray misses it (or meets it only behind the origin).
double intersect_sphere(const Eigen::Vector3d& c, double r, const Eigen::Vector3d& origin,
                        const Eigen::Vector3d& dir) noexcept;

/// Distance along the ray origin + t * dir (dir unit length) to the surface
/// of capsule @p c (the union of the cylinder between its ends and the two
/// end spheres), or +infinity when the ray misses it; 0 when the origin lies
/// inside. A sphere when both ends coincide.
double intersect_capsule(const PlacedCapsule& c, const Eigen::Vector3d& origin, const Eigen::Vector3d& dir) noexcept;

/// True when @p p lies inside or on capsule @p c.
bool capsule_contains(const PlacedCapsule& c, const Eigen::Vector3d& p) noexcept;

/// The first surface a ray meets: its distance and what it belongs to.
struct RayHit {
    double distance = 0.0;  ///< metres along the unit direction; +infinity when nothing is hit
    int box = -1;           ///< index into Scene::boxes, or -1 for the floor, a capsule or no hit
    int capsule = -1;       ///< index into Scene::robot.capsules when the robot was hit, else -1
};

/// Like cast_ray (the same distance, bit for bit), and also which surface was hit.
RayHit cast_ray_hit(const Scene& scene, const Eigen::Vector3d& origin, const Eigen::Vector3d& dir);

/// A scene prepared for casting many rays: each box's rotation is turned
/// into a matrix once instead of once per ray. Gives the same distances as
/// cast_ray, bit for bit (cast_ray's rotation does the same matrix product).
class PreparedScene {
public:
    /// Prepares @p scene (copied).
    explicit PreparedScene(Scene scene);
    /// An empty scene (the floor, no boxes) with room for @p max_boxes boxes,
    /// to be filled by assign() without allocating.
    explicit PreparedScene(std::size_t max_boxes);
    /// Prepares @p scene (copied) in place of the scene held, as the
    /// constructor does (the same distances, bit for bit). Allocates nothing
    /// when @p scene has at most capacity() boxes (the robot's capsules have
    /// a fixed capacity); with more it returns false and keeps the scene it held.
    bool assign(const Scene& scene) noexcept;
    /// Replaces only the robot's capsules of the scene held (@p robot.count
    /// at most kMaxRobotCapsules, else false and nothing changes). Allocates nothing.
    bool set_robot(const RobotPose& robot) noexcept;
    /// Boxes assign() takes without allocating.
    [[nodiscard]] std::size_t capacity() const noexcept;
    /// The first surface along origin + t * dir (dir unit length), as cast_ray_hit.
    [[nodiscard]] RayHit cast(const Eigen::Vector3d& origin, const Eigen::Vector3d& dir) const;
    /// cast() testing only box i where bit i of @p boxes is set (boxes from
    /// 64 on always), capsule j where bit j of @p capsules is set, and the
    /// floor only when @p floor: the same hit as cast() whenever the ray
    /// misses every object left out.
    [[nodiscard]] RayHit cast_some(const Eigen::Vector3d& origin, const Eigen::Vector3d& dir, std::uint64_t boxes,
                                   std::uint64_t capsules, bool floor = true) const noexcept;
    /// The scene.
    [[nodiscard]] const Scene& scene() const { return scene_; }

private:
    Scene scene_;
    std::vector<Eigen::Matrix3d> inverse_rotation_;
};

/// One sensor's pixel rays, computed once: each pixel's unit direction in
/// the workcell frame and the length of its camera ray (u - cx) / fx,
/// (v - cy) / fy, 1, exactly as render_depth_into computes them per frame.
/// About 32 bytes per pixel (10 MB for 640 x 480).
class SensorRays {
public:
    /// The rays of @p sensor (allocates).
    explicit SensorRays(const SensorSpec& sensor);
    /// The sensor.
    [[nodiscard]] const SensorSpec& sensor() const noexcept { return sensor_; }
    /// Pixel i's (row-major) unit direction.
    [[nodiscard]] const Eigen::Vector3d& direction(std::size_t i) const noexcept { return direction_[i]; }
    /// Pixel i's camera ray length (range = depth x this).
    [[nodiscard]] double ray_length(std::size_t i) const noexcept { return length_[i]; }

private:
    SensorSpec sensor_;
    std::vector<Eigen::Vector3d> direction_;
    std::vector<double> length_;
};

/// A sensor's view of a static background (floor and boxes), cast once, onto
/// which frames with moving objects are rendered: only the pixels whose ray
/// may meet a moving object are cast again. About 44 bytes per pixel.
class BackgroundView {
public:
    /// @p sensor's rays and its view of @p background (allocates).
    BackgroundView(const SensorSpec& sensor, const Scene& background);
    /// The image render_depth_into gives for the background plus @p moving's
    /// boxes and robot (its floor flag is ignored), bit for bit, into
    /// @p depth (exactly width x height values, else false and nothing
    /// written). Allocates nothing.
    [[nodiscard]] bool render_into(const PreparedScene& moving, Span<float> depth) const noexcept;

private:
    SensorRays rays_;
    std::vector<double> distance_;  ///< per pixel: the background's first surface along the ray (inf: none)
    std::vector<float> depth_;      ///< per pixel: the background's image
};

/// render_depth with a prepared scene: the same image, faster.
void render_depth(const SensorSpec& sensor, const PreparedScene& scene, std::vector<float>& depth);

/// render_depth into caller storage: @p depth must hold exactly width *
/// height values (else false, nothing written). Allocates nothing; the same
/// image, bit for bit (render_depth is this function on a vector).
bool render_depth_into(const SensorSpec& sensor, const PreparedScene& scene, Span<float> depth) noexcept;
/// render_depth_into with the sensor's rays computed once (@p rays): the
/// same image, bit for bit, without the per-pixel direction arithmetic.
bool render_depth_into(const SensorRays& rays, const PreparedScene& scene, Span<float> depth) noexcept;

/// True when @p p lies inside or on @p box.
bool box_contains(const Box& box, const Eigen::Vector3d& p);

/// A rendered frame: depth images of every sensor and the SensorReading
/// descriptions that point into them (valid while the frame lives).
struct SimulatedFrame {
    std::vector<std::vector<float>> depth;  ///< one image per sensor
    std::vector<SensorReading> readings;    ///< one description per sensor
};

/// Appends to @p frame one depth-image reading per sensor of @p sensors,
/// pointing into frame.depth (which must hold one image per sensor).
void add_readings(const std::vector<SensorSpec>& sensors, SimulatedFrame& frame);

/// Renders every sensor of @p sensors looking at @p scene.
SimulatedFrame render_frame(const std::vector<SensorSpec>& sensors, const Scene& scene);

/// The depth-image reading of @p sensor over @p depth (its pose, intrinsics
/// and max range), as add_readings and render_frame make it.
SensorReading depth_reading(const SensorSpec& sensor, Span<const float> depth) noexcept;

/// render_frame into caller storage, for a cycle that must not allocate:
/// sensor i's image goes to @p depth[i] (exactly width * height values) and
/// its reading, pointing into @p depth[i], to @p readings[i]. False, with
/// nothing written, when @p depth or @p readings do not hold one entry per
/// sensor or an image has the wrong size. Allocates nothing; the same images
/// and readings as render_frame, bit for bit.
bool render_frame_into(const std::vector<SensorSpec>& sensors, const PreparedScene& scene,
                       Span<const Span<float>> depth, Span<SensorReading> readings) noexcept;

}  // namespace cellguard::sim

#endif  // CELLGUARD_HOST_SIM_WORKCELL_HPP
