// SPDX-FileCopyrightText: 2026 The cellguard authors
// SPDX-License-Identifier: Apache-2.0
#include "cellguard/host/sim/workcell.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <utility>

namespace cellguard::sim {

namespace {
constexpr double kPi = 3.14159265358979323846;
double deg2rad(double d) { return d * kPi / 180.0; }

// Pixels of the sensor's image (the size render_depth gives its vector).
std::size_t image_size(const SensorSpec& sensor) noexcept {
    return static_cast<std::size_t>(sensor.width) * static_cast<std::size_t>(sensor.height);
}

// Slab test of a ray against a box rotated by yaw about its centre, the
// inverse rotation given as a matrix.
double intersect_box_prepared(const Box& b, const Eigen::Matrix3d& inv_yaw, const Eigen::Vector3d& origin,
                              const Eigen::Vector3d& dir) {
    const Eigen::Vector3d o = inv_yaw * (origin - b.center);
    const Eigen::Vector3d d = inv_yaw * dir;
    const Eigen::Vector3d half = 0.5 * b.size;
    double t0 = 0.0;
    double t1 = std::numeric_limits<double>::infinity();
    for (int a = 0; a < 3; ++a) {
        if (std::fabs(d[a]) < 1e-15) {
            if (o[a] < -half[a] || o[a] > half[a]) {
                return std::numeric_limits<double>::infinity();
            }
            continue;
        }
        double ta = (-half[a] - o[a]) / d[a];
        double tb = (half[a] - o[a]) / d[a];
        if (ta > tb) {
            std::swap(ta, tb);
        }
        t0 = std::fmax(t0, ta);
        t1 = std::fmin(t1, tb);
        if (t0 > t1) {
            return std::numeric_limits<double>::infinity();
        }
    }
    return t0;
}

// The entry distance of the ray into the cylinder of radius r about the
// segment a + s u, 0 <= s <= len (u unit), through its side only (the end
// discs lie inside the capsule's spheres); +infinity when it misses or runs
// parallel to the axis.
double intersect_cylinder_side(const Eigen::Vector3d& a, const Eigen::Vector3d& u, double len, double r,
                               const Eigen::Vector3d& origin, const Eigen::Vector3d& dir) noexcept {
    const Eigen::Vector3d oa = origin - a;
    const Eigen::Vector3d d_perp = dir - dir.dot(u) * u;
    const Eigen::Vector3d o_perp = oa - oa.dot(u) * u;
    const double qa = d_perp.squaredNorm();
    if (qa < 1e-18) {
        return std::numeric_limits<double>::infinity();
    }
    const double qb = d_perp.dot(o_perp);
    const double h = qb * qb - qa * (o_perp.squaredNorm() - r * r);
    if (h < 0.0) {
        return std::numeric_limits<double>::infinity();
    }
    const double root = std::sqrt(h);
    if (-qb + root < 0.0) {
        return std::numeric_limits<double>::infinity();  // behind the origin
    }
    const double t = std::fmax(0.0, (-qb - root) / qa);
    const double s = (oa + t * dir).dot(u);
    return s >= 0.0 && s <= len ? t : std::numeric_limits<double>::infinity();
}

Eigen::Vector3d point_of(const double (&p)[3]) noexcept { return {p[0], p[1], p[2]}; }

// intersect_box_prepared with the rotation made here (the product
// AngleAxis * vector computes through the same matrix).
double intersect_box(const Box& b, const Eigen::Vector3d& origin, const Eigen::Vector3d& dir) {
    return intersect_box_prepared(b, Eigen::AngleAxisd(-b.yaw, Eigen::Vector3d::UnitZ()).toRotationMatrix(), origin,
                                  dir);
}
}  // namespace

double intersect_sphere(const Eigen::Vector3d& c, double r, const Eigen::Vector3d& origin,
                        const Eigen::Vector3d& dir) noexcept {
    const Eigen::Vector3d oc = origin - c;
    const double b = dir.dot(oc);
    const double h = b * b - (oc.squaredNorm() - r * r);
    if (h < 0.0) {
        return std::numeric_limits<double>::infinity();
    }
    const double root = std::sqrt(h);
    if (-b + root < 0.0) {
        return std::numeric_limits<double>::infinity();  // behind the origin
    }
    return std::fmax(0.0, -b - root);
}

double intersect_capsule(const PlacedCapsule& c, const Eigen::Vector3d& origin, const Eigen::Vector3d& dir) noexcept {
    // A capsule is the union of two spheres and a cylinder: a ray enters it
    // where it first enters one of them.
    const Eigen::Vector3d a = point_of(c.a);
    const Eigen::Vector3d b = point_of(c.b);
    double t = std::fmin(intersect_sphere(a, c.radius, origin, dir), intersect_sphere(b, c.radius, origin, dir));
    const double len = (b - a).norm();
    if (len > 0.0) {
        t = std::fmin(t, intersect_cylinder_side(a, (b - a) / len, len, c.radius, origin, dir));
    }
    return t;
}

bool capsule_contains(const PlacedCapsule& c, const Eigen::Vector3d& p) noexcept {
    const Eigen::Vector3d a = point_of(c.a);
    const Eigen::Vector3d ab = point_of(c.b) - a;
    const double len2 = ab.squaredNorm();
    const double s = len2 > 0.0 ? std::fmin(1.0, std::fmax(0.0, (p - a).dot(ab) / len2)) : 0.0;
    return (p - (a + s * ab)).squaredNorm() <= c.radius * c.radius;
}

namespace {
// The robot's nearer hit, if any, into @p hit.
void cast_robot(const RobotPose& robot, const Eigen::Vector3d& origin, const Eigen::Vector3d& dir,
                RayHit& hit) noexcept {
    const std::size_t n = std::min<std::size_t>(robot.count, kMaxRobotCapsules);
    for (std::size_t i = 0; i < n; ++i) {
        const double t = intersect_capsule(robot.capsules[i], origin, dir);
        if (t < hit.distance) {
            hit.distance = t;
            hit.box = -1;
            hit.capsule = static_cast<int>(i);
        }
    }
}
}  // namespace

PreparedScene::PreparedScene(Scene scene) : scene_(std::move(scene)) {
    for (const Box& b : scene_.boxes) {
        inverse_rotation_.push_back(Eigen::AngleAxisd(-b.yaw, Eigen::Vector3d::UnitZ()).toRotationMatrix());
    }
}

PreparedScene::PreparedScene(std::size_t max_boxes) {
    scene_.boxes.reserve(max_boxes);
    inverse_rotation_.reserve(max_boxes);
}

bool PreparedScene::assign(const Scene& scene) noexcept {
    if (scene.boxes.size() > capacity()) {
        return false;
    }
    // Within the reserved capacity clear() and push_back() never reallocate.
    if (scene.robot.count > kMaxRobotCapsules) {
        return false;
    }
    scene_.floor = scene.floor;
    scene_.robot = scene.robot;
    scene_.boxes.clear();
    inverse_rotation_.clear();
    for (const Box& b : scene.boxes) {
        scene_.boxes.push_back(b);
        inverse_rotation_.push_back(Eigen::AngleAxisd(-b.yaw, Eigen::Vector3d::UnitZ()).toRotationMatrix());
    }
    return true;
}

bool PreparedScene::set_robot(const RobotPose& robot) noexcept {
    if (robot.count > kMaxRobotCapsules) {
        return false;
    }
    scene_.robot = robot;
    return true;
}

std::size_t PreparedScene::capacity() const noexcept {
    return std::min(scene_.boxes.capacity(), inverse_rotation_.capacity());
}

RayHit PreparedScene::cast_some(const Eigen::Vector3d& origin, const Eigen::Vector3d& dir, std::uint64_t boxes,
                                std::uint64_t capsules, bool floor) const noexcept {
    RayHit hit;
    hit.distance = std::numeric_limits<double>::infinity();
    if (floor && scene_.floor && dir.z() < 0.0) {
        hit.distance = -origin.z() / dir.z();
    }
    for (std::size_t i = 0; i < scene_.boxes.size(); ++i) {
        if (i < 64U && ((boxes >> i) & 1U) == 0U) {
            continue;
        }
        const double t = intersect_box_prepared(scene_.boxes[i], inverse_rotation_[i], origin, dir);
        if (t < hit.distance) {
            hit.distance = t;
            hit.box = static_cast<int>(i);
        }
    }
    const std::size_t n = std::min<std::size_t>(scene_.robot.count, kMaxRobotCapsules);
    for (std::size_t i = 0; i < n; ++i) {
        if (((capsules >> i) & 1U) == 0U) {
            continue;
        }
        const double t = intersect_capsule(scene_.robot.capsules[i], origin, dir);
        if (t < hit.distance) {
            hit.distance = t;
            hit.box = -1;
            hit.capsule = static_cast<int>(i);
        }
    }
    return hit;
}

RayHit PreparedScene::cast(const Eigen::Vector3d& origin, const Eigen::Vector3d& dir) const {
    RayHit hit;
    hit.distance = std::numeric_limits<double>::infinity();
    if (scene_.floor && dir.z() < 0.0) {
        hit.distance = -origin.z() / dir.z();
    }
    for (std::size_t i = 0; i < scene_.boxes.size(); ++i) {
        const double t = intersect_box_prepared(scene_.boxes[i], inverse_rotation_[i], origin, dir);
        if (t < hit.distance) {
            hit.distance = t;
            hit.box = static_cast<int>(i);
        }
    }
    cast_robot(scene_.robot, origin, dir, hit);
    return hit;
}

void render_depth(const SensorSpec& sensor, const PreparedScene& scene, std::vector<float>& depth) {
    depth.assign(image_size(sensor), 0.0F);
    (void)render_depth_into(sensor, scene, Span<float>(depth.data(), depth.size()));
}

namespace {

// A pixel rectangle [u0, u1] x [v0, v1] (inclusive) that holds every pixel
// whose ray can meet an object; the whole image when that is not known.
struct PixelRect {
    std::int32_t u0 = std::numeric_limits<std::int32_t>::min();
    std::int32_t u1 = std::numeric_limits<std::int32_t>::max();
    std::int32_t v0 = std::numeric_limits<std::int32_t>::min();
    std::int32_t v1 = std::numeric_limits<std::int32_t>::max();
    [[nodiscard]] bool holds(std::int32_t u, std::int32_t v) const noexcept {
        return u >= u0 && u <= u1 && v >= v0 && v <= v1;
    }
};

// The rectangle of the eight corners @p corners (workcell frame) projected
// into the sensor, grown by 2 pixels. A ray that meets the convex hull of
// the corners meets it at a point that projects into the hull of the
// projected corners (all in front of the camera: projection keeps convex
// sets convex), so its pixel lies in the rectangle; the margin covers
// rounding. A corner within 1 mm of the camera plane or behind it: the whole image.
PixelRect project_corners(const Eigen::Vector3d (&corners)[8], const Eigen::Isometry3d& world_to_camera,
                          const PinholeIntrinsics& k) noexcept {
    double u_min = std::numeric_limits<double>::infinity();
    double u_max = -std::numeric_limits<double>::infinity();
    double v_min = u_min;
    double v_max = u_max;
    for (const Eigen::Vector3d& c : corners) {
        const Eigen::Vector3d p = world_to_camera * c;
        if (!(p.z() > 1e-3)) {
            return PixelRect{};
        }
        const double u = k.fx * p.x() / p.z() + k.cx;
        const double v = k.fy * p.y() / p.z() + k.cy;
        u_min = std::fmin(u_min, u);
        u_max = std::fmax(u_max, u);
        v_min = std::fmin(v_min, v);
        v_max = std::fmax(v_max, v);
    }
    const auto clamp = [](double x) { return static_cast<std::int32_t>(std::fmax(-1e6, std::fmin(1e6, x))); };
    return PixelRect{clamp(std::floor(u_min) - 2.0), clamp(std::ceil(u_max) + 2.0), clamp(std::floor(v_min) - 2.0),
                     clamp(std::ceil(v_max) + 2.0)};
}

PixelRect box_rect(const Box& b, const Eigen::Isometry3d& world_to_camera, const PinholeIntrinsics& k) noexcept {
    const Eigen::Matrix3d yaw = Eigen::AngleAxisd(b.yaw, Eigen::Vector3d::UnitZ()).toRotationMatrix();
    Eigen::Vector3d corners[8];
    for (unsigned i = 0U; i < 8U; ++i) {
        const Eigen::Vector3d s((i & 1U) != 0U ? 0.5 : -0.5, (i & 2U) != 0U ? 0.5 : -0.5, (i & 4U) != 0U ? 0.5 : -0.5);
        // 1 mm more than the box: its rotation here and the ray caster's inverse one round differently.
        corners[i] = b.center + yaw * (s.cwiseProduct(b.size) + 2e-3 * s);
    }
    return project_corners(corners, world_to_camera, k);
}

PixelRect capsule_rect(const PlacedCapsule& c, const Eigen::Isometry3d& world_to_camera,
                       const PinholeIntrinsics& k) noexcept {
    const Eigen::Vector3d a = point_of(c.a);
    const Eigen::Vector3d b = point_of(c.b);
    const Eigen::Vector3d lo = a.cwiseMin(b).array() - (c.radius + 1e-3);
    const Eigen::Vector3d hi = a.cwiseMax(b).array() + (c.radius + 1e-3);
    Eigen::Vector3d corners[8];
    for (unsigned i = 0U; i < 8U; ++i) {
        corners[i] = Eigen::Vector3d((i & 1U) != 0U ? hi.x() : lo.x(), (i & 2U) != 0U ? hi.y() : lo.y(),
                                     (i & 4U) != 0U ? hi.z() : lo.z());
    }
    return project_corners(corners, world_to_camera, k);
}

// The objects' pixel rectangles of one image (the first 64 boxes, every capsule).
struct SceneRects {
    PixelRect boxes[64];
    PixelRect capsules[kMaxRobotCapsules];
    std::size_t box_count = 0U;
    std::size_t capsule_count = 0U;

    SceneRects(const Scene& scene, const Eigen::Isometry3d& pose, const PinholeIntrinsics& k) noexcept {
        const Eigen::Isometry3d world_to_camera = pose.inverse();
        box_count = std::min<std::size_t>(scene.boxes.size(), 64U);
        for (std::size_t i = 0U; i < box_count; ++i) {
            boxes[i] = box_rect(scene.boxes[i], world_to_camera, k);
        }
        capsule_count = std::min<std::size_t>(scene.robot.count, kMaxRobotCapsules);
        for (std::size_t i = 0U; i < capsule_count; ++i) {
            capsules[i] = capsule_rect(scene.robot.capsules[i], world_to_camera, k);
        }
    }
    // The objects whose rectangle holds pixel (u, v), as cast_some's masks.
    void masks(std::int32_t u, std::int32_t v, std::uint64_t& box_mask, std::uint64_t& capsule_mask) const noexcept {
        box_mask = 0U;
        capsule_mask = 0U;
        for (std::size_t i = 0U; i < box_count; ++i) {
            box_mask |= static_cast<std::uint64_t>(boxes[i].holds(u, v)) << i;
        }
        for (std::size_t i = 0U; i < capsule_count; ++i) {
            capsule_mask |= static_cast<std::uint64_t>(capsules[i].holds(u, v)) << i;
        }
    }
};

// The image of @p sensor: pixel (u, v)'s direction and camera ray length
// come from @p ray(u, v, dir, length); each ray is tested only against the
// objects whose pixel rectangle holds its pixel (the others it misses).
template <typename RayOf>
void render_culled(const SensorSpec& sensor, const PreparedScene& scene, Span<float> depth, RayOf ray) noexcept {
    const PinholeIntrinsics k = sensor.intrinsics();
    const Eigen::Isometry3d pose = sensor.pose();
    const SceneRects rects(scene.scene(), pose, k);
    std::fill(depth.begin(), depth.end(), 0.0F);
    Eigen::Vector3d dir;
    double length = 0.0;
    for (std::int32_t v = 0; v < k.height; ++v) {
        for (std::int32_t u = 0; u < k.width; ++u) {
            ray(u, v, dir, length);
            std::uint64_t box_mask = 0U;
            std::uint64_t capsule_mask = 0U;
            rects.masks(u, v, box_mask, capsule_mask);
            const double t = scene.cast_some(pose.translation(), dir, box_mask, capsule_mask).distance;
            const double z = t / length;
            if (std::isfinite(t) && t <= static_cast<double>(sensor.max_range)) {
                depth[static_cast<std::size_t>(v) * static_cast<std::size_t>(k.width) + static_cast<std::size_t>(u)] =
                    static_cast<float>(z);
            }
        }
    }
}

}  // namespace

SensorRays::SensorRays(const SensorSpec& sensor) : sensor_(sensor) {
    const PinholeIntrinsics k = sensor.intrinsics();
    const Eigen::Isometry3d pose = sensor.pose();
    direction_.reserve(image_size(sensor));
    length_.reserve(image_size(sensor));
    for (std::int32_t v = 0; v < k.height; ++v) {
        for (std::int32_t u = 0; u < k.width; ++u) {
            // render_depth_into's arithmetic, once.
            const Eigen::Vector3d ray_cam((u - k.cx) / k.fx, (v - k.cy) / k.fy, 1.0);
            direction_.push_back((pose.linear() * ray_cam).normalized());
            length_.push_back(ray_cam.norm());
        }
    }
}

BackgroundView::BackgroundView(const SensorSpec& sensor, const Scene& background)
    : rays_(sensor), distance_(image_size(sensor)), depth_(image_size(sensor), 0.0F) {
    const PreparedScene scene(background);
    const Eigen::Vector3d origin = sensor.pose().translation();
    for (std::size_t i = 0U; i < distance_.size(); ++i) {
        distance_[i] = scene.cast(origin, rays_.direction(i)).distance;
        const double t = distance_[i];
        if (std::isfinite(t) && t <= static_cast<double>(sensor.max_range)) {
            depth_[i] = static_cast<float>(t / rays_.ray_length(i));
        }
    }
}

bool BackgroundView::render_into(const PreparedScene& moving, Span<float> depth) const noexcept {
    const SensorSpec& sensor = rays_.sensor();
    if (depth.size() != depth_.size()) {
        return false;
    }
    std::copy(depth_.begin(), depth_.end(), depth.begin());
    const PinholeIntrinsics k = sensor.intrinsics();
    const Eigen::Isometry3d pose = sensor.pose();
    const SceneRects rects(moving.scene(), pose, k);
    // Where no moving object can be met the background's image stands; the
    // first surface elsewhere is the nearer of the background's and the
    // moving objects' (each object's distance is computed on its own, so the
    // minimum is the whole scene's, bit for bit).
    PixelRect all{std::numeric_limits<std::int32_t>::max(), std::numeric_limits<std::int32_t>::min(),
                  std::numeric_limits<std::int32_t>::max(), std::numeric_limits<std::int32_t>::min()};
    const auto cover = [&all](const PixelRect& r) {
        all.u0 = std::min(all.u0, r.u0);
        all.u1 = std::max(all.u1, r.u1);
        all.v0 = std::min(all.v0, r.v0);
        all.v1 = std::max(all.v1, r.v1);
    };
    for (std::size_t i = 0U; i < rects.box_count; ++i) {
        cover(rects.boxes[i]);
    }
    for (std::size_t i = 0U; i < rects.capsule_count; ++i) {
        cover(rects.capsules[i]);
    }
    const std::size_t n = moving.scene().boxes.size();
    if (n > rects.box_count) {  // boxes beyond the first 64 have no rectangle: every pixel
        cover(PixelRect{});
    }
    const std::int32_t v_end = std::min(all.v1, k.height - 1);
    const std::int32_t u_end = std::min(all.u1, k.width - 1);
    for (std::int32_t v = std::max(all.v0, 0); v <= v_end; ++v) {
        for (std::int32_t u = std::max(all.u0, 0); u <= u_end; ++u) {
            std::uint64_t box_mask = 0U;
            std::uint64_t capsule_mask = 0U;
            rects.masks(u, v, box_mask, capsule_mask);
            const std::size_t i = static_cast<std::size_t>(v) * static_cast<std::size_t>(k.width) +
                                  static_cast<std::size_t>(u);
            if (box_mask == 0U && capsule_mask == 0U && n <= rects.box_count) {
                continue;
            }
            const double t = std::fmin(
                distance_[i],
                moving.cast_some(pose.translation(), rays_.direction(i), box_mask, capsule_mask, false).distance);
            depth[i] = std::isfinite(t) && t <= static_cast<double>(sensor.max_range)
                           ? static_cast<float>(t / rays_.ray_length(i))
                           : 0.0F;
        }
    }
    return true;
}

bool render_depth_into(const SensorSpec& sensor, const PreparedScene& scene, Span<float> depth) noexcept {
    if (depth.size() != image_size(sensor)) {
        return false;
    }
    const PinholeIntrinsics k = sensor.intrinsics();
    const Eigen::Isometry3d pose = sensor.pose();
    render_culled(sensor, scene, depth,
                  [&k, &pose](std::int32_t u, std::int32_t v, Eigen::Vector3d& dir, double& length) {
                      const Eigen::Vector3d ray_cam((u - k.cx) / k.fx, (v - k.cy) / k.fy, 1.0);
                      dir = (pose.linear() * ray_cam).normalized();
                      length = ray_cam.norm();
                  });
    return true;
}

bool render_depth_into(const SensorRays& rays, const PreparedScene& scene, Span<float> depth) noexcept {
    const SensorSpec& sensor = rays.sensor();
    if (depth.size() != image_size(sensor)) {
        return false;
    }
    const auto width = static_cast<std::size_t>(sensor.width);
    render_culled(sensor, scene, depth,
                  [&rays, width](std::int32_t u, std::int32_t v, Eigen::Vector3d& dir, double& length) {
                      const std::size_t i = static_cast<std::size_t>(v) * width + static_cast<std::size_t>(u);
                      dir = rays.direction(i);
                      length = rays.ray_length(i);
                  });
    return true;
}

Eigen::Isometry3d SensorSpec::pose() const {
    const Eigen::Vector3d forward = (target - position).normalized();
    const Eigen::Vector3d right = forward.cross(Eigen::Vector3d::UnitZ()).normalized();
    const Eigen::Vector3d down = forward.cross(right);
    Eigen::Isometry3d t = Eigen::Isometry3d::Identity();
    t.linear().col(0) = right;
    t.linear().col(1) = down;
    t.linear().col(2) = forward;
    t.translation() = position;
    return t;
}

PinholeIntrinsics SensorSpec::intrinsics() const {
    PinholeIntrinsics k;
    k.width = width;
    k.height = height;
    if (has_intrinsics) {
        k.fx = fx;
        k.fy = fy;
        k.cx = cx;
        k.cy = cy;
        return k;
    }
    k.fx = 0.5 * width / std::tan(0.5 * deg2rad(hfov_deg));
    k.fy = 0.5 * height / std::tan(0.5 * deg2rad(vfov_deg));
    k.cx = 0.5 * (width - 1);
    k.cy = 0.5 * (height - 1);
    return k;
}

void SensorSpec::set_intrinsics(double focal_x, double focal_y, double centre_x, double centre_y) {
    has_intrinsics = true;
    fx = focal_x;
    fy = focal_y;
    cx = centre_x;
    cy = centre_y;
    hfov_deg = 2.0 * std::atan(0.5 * width / focal_x) * 180.0 / kPi;
    vfov_deg = 2.0 * std::atan(0.5 * height / focal_y) * 180.0 / kPi;
}

std::vector<SensorSpec> paper_sensors() {
    const Eigen::Vector3d target(0.0, 0.0, 0.0);  // the centre of the floor: every pixel meets the floor within 10 m
    std::vector<SensorSpec> s(4);
    const double c = 1.9;
    const double h = 1.9;
    s[0] = SensorSpec{"lidar-a", {-c, -c, h}, target, 176, 144, 43.6, 34.6, 10.0F};
    s[1] = SensorSpec{"lidar-b", {c, c, h}, target, 176, 144, 43.6, 34.6, 10.0F};
    s[2] = SensorSpec{"stereo-a", {c, -c, h}, target, 320, 240, 60.0, 45.0, 10.0F};
    s[3] = SensorSpec{"stereo-b", {-c, c, h}, target, 320, 240, 60.0, 45.0, 10.0F};
    return s;
}

Scene reference_scene() {
    Scene s;
    s.boxes.push_back(Box{{-0.35, 0.2, 0.3}, {0.5, 0.4, 0.6}, 0.0, true});
    s.boxes.push_back(Box{{0.4, -0.25, 0.2}, {0.4, 0.6, 0.4}, 0.3, true});
    return s;
}

double cast_ray(const Scene& scene, const Eigen::Vector3d& origin, const Eigen::Vector3d& dir) {
    double best = std::numeric_limits<double>::infinity();
    if (scene.floor && dir.z() < 0.0) {
        best = -origin.z() / dir.z();
    }
    for (const Box& b : scene.boxes) {
        best = std::fmin(best, intersect_box(b, origin, dir));
    }
    const std::size_t n = std::min<std::size_t>(scene.robot.count, kMaxRobotCapsules);
    for (std::size_t i = 0; i < n; ++i) {
        best = std::fmin(best, intersect_capsule(scene.robot.capsules[i], origin, dir));
    }
    return best;
}

RayHit cast_ray_hit(const Scene& scene, const Eigen::Vector3d& origin, const Eigen::Vector3d& dir) {
    RayHit hit;
    hit.distance = std::numeric_limits<double>::infinity();
    if (scene.floor && dir.z() < 0.0) {
        hit.distance = -origin.z() / dir.z();
    }
    for (std::size_t i = 0; i < scene.boxes.size(); ++i) {
        const double t = intersect_box(scene.boxes[i], origin, dir);
        if (t < hit.distance) {
            hit.distance = t;
            hit.box = static_cast<int>(i);
        }
    }
    cast_robot(scene.robot, origin, dir, hit);
    return hit;
}

bool box_contains(const Box& box, const Eigen::Vector3d& p) {
    const Eigen::AngleAxisd inv_yaw(-box.yaw, Eigen::Vector3d::UnitZ());
    const Eigen::Vector3d local = inv_yaw * (p - box.center);
    const Eigen::Vector3d half = 0.5 * box.size;
    return std::fabs(local.x()) <= half.x() && std::fabs(local.y()) <= half.y() && std::fabs(local.z()) <= half.z();
}

void render_depth(const SensorSpec& sensor, const Scene& scene, std::vector<float>& depth) {
    // One ray caster: the prepared scene casts exactly the plain scene's distances (tested).
    render_depth(sensor, PreparedScene(scene), depth);
}

SensorReading depth_reading(const SensorSpec& sensor, Span<const float> depth) noexcept {
    SensorReading r;
    r.pose = sensor.pose();
    r.kind = SensorDataKind::kDepthImage;
    r.depth = depth;
    r.intrinsics = sensor.intrinsics();
    r.max_range = sensor.max_range;
    return r;
}

void add_readings(const std::vector<SensorSpec>& sensors, SimulatedFrame& frame) {
    for (std::size_t i = 0; i < sensors.size(); ++i) {
        frame.readings.push_back(
            depth_reading(sensors[i], Span<const float>(frame.depth[i].data(), frame.depth[i].size())));
    }
}

SimulatedFrame render_frame(const std::vector<SensorSpec>& sensors, const Scene& scene) {
    SimulatedFrame f;
    f.depth.resize(sensors.size());
    for (std::size_t i = 0; i < sensors.size(); ++i) {
        render_depth(sensors[i], scene, f.depth[i]);
    }
    add_readings(sensors, f);
    return f;
}

bool render_frame_into(const std::vector<SensorSpec>& sensors, const PreparedScene& scene,
                       Span<const Span<float>> depth, Span<SensorReading> readings) noexcept {
    if (depth.size() != sensors.size() || readings.size() != sensors.size()) {
        return false;
    }
    for (std::size_t i = 0; i < sensors.size(); ++i) {
        if (depth[i].size() != image_size(sensors[i])) {
            return false;
        }
    }
    for (std::size_t i = 0; i < sensors.size(); ++i) {
        (void)render_depth_into(sensors[i], scene, depth[i]);
        readings[i] = depth_reading(sensors[i], depth[i]);
    }
    return true;
}

}  // namespace cellguard::sim
