// Copyright (c) 2026, the activecal authors.
// SPDX-License-Identifier: BSD-3-Clause

#include "activecal/cell/cell_checker.h"

#include <fcl/fcl.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>
#include <set>

#include "activecal/core/enum_name_list.h"
#include "activecal/core/kinematics.h"
#include "cell_internal.h"

namespace activecal {
namespace {

using internal::Compose;

// Angles within this of a limit count as on it (rad); joint values within
// this of a margin's end count as on it (rad or m).
constexpr double kAngleTolerance = 1e-9;
constexpr double kJointTolerance = 1e-12;
// A target this close to a shape's surface, outside, is on it (m).
constexpr double kMountToleranceM = 1e-9;

fcl::Transform3d ToFcl(const FixedTransform& t) {
  fcl::Transform3d f = fcl::Transform3d::Identity();
  f.linear() = t.rotation;
  f.translation() = t.translation;
  return f;
}

std::shared_ptr<fcl::CollisionGeometryd> MakeGeometry(const CollisionShape& s) {
  switch (s.type) {
    case ShapeType::kBox:
      return std::make_shared<fcl::Boxd>(s.size_m.x(), s.size_m.y(),
                                         s.size_m.z());
    case ShapeType::kCylinder:
      return std::make_shared<fcl::Cylinderd>(s.radius_m, s.length_m);
    case ShapeType::kCapsule:
      return std::make_shared<fcl::Capsuled>(s.radius_m, s.length_m);
    case ShapeType::kSphere:
      return std::make_shared<fcl::Sphered>(s.radius_m);
    case ShapeType::kMesh: {
      auto mesh = std::make_shared<fcl::BVHModel<fcl::OBBRSSd>>();
      std::vector<fcl::Triangle> triangles;
      triangles.reserve(s.triangles.size());
      for (const auto& t : s.triangles)
        triangles.emplace_back(t[0], t[1], t[2]);
      mesh->beginModel();
      mesh->addSubModel(s.vertices, triangles);
      mesh->endModel();
      return mesh;
    }
  }
  return nullptr;
}

// The least value of normal . x over the shape (world frame pose R, t):
// its support in -normal.
double LowestAlong(const CollisionShape& s, const Eigen::Matrix3d& R,
                   const Eigen::Vector3d& t, const Eigen::Vector3d& normal) {
  const Eigen::Vector3d n_local = R.transpose() * normal;
  const double centre = normal.dot(t);
  switch (s.type) {
    case ShapeType::kBox:
      return centre - 0.5 * (n_local.cwiseAbs().dot(s.size_m));
    case ShapeType::kCylinder: {
      const double along = std::abs(n_local.z());
      const double across = std::sqrt(std::max(0.0, 1.0 - along * along));
      return centre - 0.5 * s.length_m * along - s.radius_m * across;
    }
    case ShapeType::kCapsule:
      return centre - 0.5 * s.length_m * std::abs(n_local.z()) - s.radius_m;
    case ShapeType::kSphere:
      return centre - s.radius_m;
    case ShapeType::kMesh: {
      double lowest = std::numeric_limits<double>::infinity();
      for (const Eigen::Vector3d& v : s.vertices) {
        lowest = std::min(lowest, n_local.dot(v));
      }
      return centre + lowest;
    }
  }
  return centre;
}

// Distance from point p to the segment [a, b].
double PointSegmentDistance(const Eigen::Vector3d& p, const Eigen::Vector3d& a,
                            const Eigen::Vector3d& b) {
  const Eigen::Vector3d d = b - a;
  const double len2 = d.squaredNorm();
  double s = len2 > 0 ? (p - a).dot(d) / len2 : 0.0;
  s = std::clamp(s, 0.0, 1.0);
  return (p - (a + s * d)).norm();
}

double AngleBetween(const Eigen::Vector3d& u, const Eigen::Vector3d& v) {
  return std::atan2(u.cross(v).norm(), u.dot(v));
}

}  // namespace

constexpr EnumName<RejectionReason> kRejectionReasonNames[] = {
    {RejectionReason::kNone, "none"},
    {RejectionReason::kJointMargin, "joint_margin"},
    {RejectionReason::kOutOfRange, "out_of_range"},
    {RejectionReason::kOutOfView, "out_of_view"},
    {RejectionReason::kFacingAway, "facing_away"},
    {RejectionReason::kSelfCollision, "self_collision"},
    {RejectionReason::kObstacle, "obstacle"},
    {RejectionReason::kLineOfSight, "line_of_sight"}};
ACTIVECAL_ENUM_STRING_FUNCTIONS(RejectionReason, kRejectionReasonNames)

// The labels of the feasibility reports, in RejectionReason's order.
constexpr const char* kRejectionReasonLabels[] = {
    "feasible",    "joint margin",         "out of range",
    "out of view", "target facing away",   "self-collision",
    "obstacle",    "line of sight blocked"};

const char* RejectionReasonLabel(RejectionReason reason) {
  return EnumToString(kRejectionReasonLabels, reason);
}

struct CellChecker::Impl {
  struct Shape {
    int body = 0;
    int frame = 0;
    FixedTransform in_frame;  // body in_frame x shape pose
    const CollisionShape* source = nullptr;
    std::shared_ptr<fcl::CollisionGeometryd> geometry;
    Eigen::Vector3d ball_centre;  // in the shape's frame
    double ball_radius = 0.0;
    // Bit t: a convex shape of the tip's frame that holds target t (its
    // mount), not an occlusion of t's lines of sight.
    uint32_t mount_of = 0;
  };
  struct SolidObstacle {
    int obstacle = 0;
    std::unique_ptr<fcl::CollisionObjectd> object;
    Eigen::Vector3d ball_centre;  // base frame
    double ball_radius = 0.0;
  };
  struct ShapePair {
    int a, b;  // shapes
  };
  struct ObstaclePair {
    int obstacle, shape;
  };
  // A viewpoint: the laser tracker, or a camera.
  struct Eye {
    Eigen::Vector3d position;
    double min_range, max_range;
    const CellCamera* camera = nullptr;  // null: no field of view
  };

  Eigen::VectorXd parameters;
  std::vector<const double*> blocks;
  std::vector<Shape> shapes;
  std::vector<SolidObstacle> solids;  // by index into the cell's obstacles
  std::vector<int> solid_of;          // obstacle -> index in solids, or -1
  std::vector<ShapePair> self_pairs;
  std::vector<std::pair<int, int>> self_body_pairs;  // distinct body pairs
  std::vector<ObstaclePair> obstacle_pairs;
  std::vector<std::pair<int, int>> obstacle_body_pairs;  // (obstacle, body)
  std::vector<Eye> eyes;
  int min_eyes = 1;
  std::vector<double> acceptance;  // per target, the device's cap applied
  fcl::DistanceRequestd distance_request;
};

struct CellChecker::Workspace::Data {
  std::vector<std::unique_ptr<fcl::CollisionObjectd>> objects;  // per shape
  std::vector<FixedTransform> frames;
  std::vector<FixedTransform> world;     // per shape
  std::vector<Eigen::Vector3d> centres;  // per shape, ball centre in base
  std::shared_ptr<fcl::Capsuled> beam;
  std::unique_ptr<fcl::CollisionObjectd> beam_object;
};

CellChecker::Workspace::Workspace() : data_(std::make_unique<Data>()) {}
CellChecker::Workspace::~Workspace() = default;

CellChecker::CellChecker() = default;
CellChecker::~CellChecker() = default;

bool CellChecker::Init(const RobotModel& model,
                       const RobotCollisionModel& robot, const Cell& cell,
                       std::string* error) {
  auto fail = [&](const std::string& what) {
    if (error) *error = what;
    return false;
  };
  model_ = model;
  robot_ = robot;
  cell_ = cell;
  impl_ = std::make_unique<Impl>();
  Impl& im = *impl_;
  const std::string where = cell.source.empty() ? "cell" : cell.source;
  if (cell.targets.size() > 32) {
    return fail(where + ": targets: at most 32, got " +
                std::to_string(cell.targets.size()));
  }
  if (cell.has_device &&
      cell.device.cameras.size() > static_cast<size_t>(kMaxCellCameras)) {
    return fail(where + ": device.cameras: at most " +
                std::to_string(kMaxCellCameras) + " cameras, got " +
                std::to_string(cell.device.cameras.size()));
  }
  // Joint margins.
  std::map<std::string, int> joint_index;
  for (int j = 0; j < model.num_joints(); ++j) {
    joint_index[model.links[j].name] = j;
  }
  margins_.resize(model.num_joints());
  for (int j = 0; j < model.num_joints(); ++j) {
    margins_[j] = model.links[j].joint_type == JointType::kPrismatic
                      ? cell.joint_margin_m
                      : cell.joint_margin_rad;
  }
  for (const auto& [name, value] : cell.joint_margin_override) {
    const auto it = joint_index.find(name);
    const auto w = cell.joint_margin_override_where.find(name);
    const std::string at = w != cell.joint_margin_override_where.end()
                               ? w->second
                               : where + ": joint margin override";
    if (it == joint_index.end()) {
      std::string names;
      for (const Link& l : model.links)
        names += (names.empty() ? "" : ", ") + l.name;
      return fail(at + ": the robot has no joint named '" + name +
                  "' (joints: " + names + ")");
    }
    margins_[it->second] = value;
  }
  for (int j = 0; j < model.num_joints(); ++j) {
    const Link& l = model.links[j];
    if (std::isfinite(l.joint_min) && std::isfinite(l.joint_max) &&
        l.joint_max - l.joint_min < 2 * margins_[j]) {
      // Where the margin was given, in its unit.
      const bool prismatic = l.joint_type == JointType::kPrismatic;
      const auto o = cell.joint_margin_override_where.find(l.name);
      std::string at =
          prismatic ? cell.joint_margin_m_where : cell.joint_margin_deg_where;
      if (o != cell.joint_margin_override_where.end()) at = o->second;
      if (at.empty()) at = where + ": joint margin";
      const double unit = prismatic ? 1.0 : M_PI / 180.0;
      char numbers[96];
      std::snprintf(numbers, sizeof(numbers),
                    "has a range of %.4g %s, narrower than twice its margin "
                    "(%.4g %s)",
                    (l.joint_max - l.joint_min) / unit, prismatic ? "m" : "deg",
                    margins_[j] / unit, prismatic ? "m" : "deg");
      return fail(at + ": joint '" + l.name + "' " + numbers);
    }
  }
  // Collision shapes.
  for (size_t b = 0; b < robot_.bodies.size(); ++b) {
    const CollisionBody& body = robot_.bodies[b];
    if (body.frame < 0 || body.frame > model.num_joints()) {
      return fail("collision body '" + body.name + "': frame out of range");
    }
    for (const CollisionShape& s : body.shapes) {
      Impl::Shape e;
      e.body = static_cast<int>(b);
      e.frame = body.frame;
      e.in_frame = Compose(body.in_frame, s.pose);
      e.source = &s;
      e.geometry = MakeGeometry(s);
      s.BoundingBall(&e.ball_centre, &e.ball_radius);
      im.shapes.push_back(std::move(e));
    }
  }
  // The targets' mounts: a beam from a point inside a convex shape leaves
  // it once, next to the target, and never enters it again.
  for (Impl::Shape& e : im.shapes) {
    if (e.frame != model.num_joints() || e.source->type == ShapeType::kMesh) {
      continue;
    }
    for (size_t t = 0; t < cell.targets.size(); ++t) {
      const Eigen::Vector3d in_tip_link =
          model.tip.rotation * cell.targets[t].xyz_m + model.tip.translation;
      const Eigen::Vector3d local = e.in_frame.rotation.transpose() *
                                    (in_tip_link - e.in_frame.translation);
      if (PointInShape(*e.source, local, kMountToleranceM)) {
        e.mount_of |= 1u << t;
      }
    }
  }
  // Skip pairs: names of bodies or obstacles.
  std::map<std::string, int> obstacle_index;
  for (size_t o = 0; o < cell.obstacles.size(); ++o) {
    obstacle_index[cell.obstacles[o].name] = static_cast<int>(o);
  }
  std::set<std::pair<int, int>> skip_bodies;     // (body, body), ordered
  std::set<std::pair<int, int>> skip_obstacles;  // (obstacle, body)
  for (size_t k = 0; k < cell.skip_pairs.size(); ++k) {
    const auto& [first, second] = cell.skip_pairs[k];
    const std::string at =
        k < cell.skip_pair_where.size() ? cell.skip_pair_where[k] : "";
    const int b1 = robot_.BodyIndex(first), b2 = robot_.BodyIndex(second);
    const auto o1 = obstacle_index.find(first),
               o2 = obstacle_index.find(second);
    if (b1 >= 0 && b2 >= 0) {
      skip_bodies.insert({std::min(b1, b2), std::max(b1, b2)});
    } else if (b1 >= 0 && o2 != obstacle_index.end()) {
      skip_obstacles.insert({o2->second, b1});
    } else if (b2 >= 0 && o1 != obstacle_index.end()) {
      skip_obstacles.insert({o1->second, b2});
    } else if (!at.empty()) {
      const std::string& unknown =
          (b1 < 0 && o1 == obstacle_index.end()) ? first : second;
      std::string names;
      for (const CollisionBody& body : robot_.bodies) {
        names += (names.empty() ? "" : ", ") + body.name;
      }
      return fail(at + ": '" + unknown +
                  "' is neither a link of the robot nor an obstacle (links: " +
                  names + ")");
    }
  }
  // Self pairs: bodies neither on the same nor on consecutive frames.
  const int num_shapes = static_cast<int>(im.shapes.size());
  for (int i = 0; i < num_shapes; ++i) {
    for (int k = i + 1; k < num_shapes; ++k) {
      const Impl::Shape &a = im.shapes[i], &b = im.shapes[k];
      if (a.body == b.body || std::abs(a.frame - b.frame) <= 1) continue;
      if (skip_bodies.count(
              {std::min(a.body, b.body), std::max(a.body, b.body)})) {
        continue;
      }
      im.self_pairs.push_back({i, k});
      const std::pair<int, int> bp(std::min(a.body, b.body),
                                   std::max(a.body, b.body));
      if (std::find(im.self_body_pairs.begin(), im.self_body_pairs.end(), bp) ==
          im.self_body_pairs.end()) {
        im.self_body_pairs.push_back(bp);
      }
    }
  }
  // Obstacles.
  im.solid_of.assign(cell.obstacles.size(), -1);
  for (size_t o = 0; o < cell.obstacles.size(); ++o) {
    const Obstacle& ob = cell.obstacles[o];
    if (!ob.plane) {
      Impl::SolidObstacle s;
      s.obstacle = static_cast<int>(o);
      s.object = std::make_unique<fcl::CollisionObjectd>(MakeGeometry(ob.shape),
                                                         ToFcl(ob.shape.pose));
      s.object->computeAABB();
      Eigen::Vector3d c;
      ob.shape.BoundingBall(&c, &s.ball_radius);
      s.ball_centre = ob.shape.pose.rotation * c + ob.shape.pose.translation;
      im.solid_of[o] = static_cast<int>(im.solids.size());
      im.solids.push_back(std::move(s));
    }
    for (int i = 0; i < num_shapes; ++i) {
      const Impl::Shape& s = im.shapes[i];
      if (s.frame == 0 || skip_obstacles.count({static_cast<int>(o), s.body})) {
        continue;
      }
      im.obstacle_pairs.push_back({static_cast<int>(o), i});
      const std::pair<int, int> op(static_cast<int>(o), s.body);
      if (std::find(im.obstacle_body_pairs.begin(),
                    im.obstacle_body_pairs.end(),
                    op) == im.obstacle_body_pairs.end()) {
        im.obstacle_body_pairs.push_back(op);
      }
    }
  }
  // The viewpoints.
  if (cell.has_device) {
    const CellDevice& d = cell.device;
    if (d.type == DeviceType::kLaserTracker) {
      im.eyes.push_back({d.position, d.min_range_m, d.max_range_m, nullptr});
    } else {
      for (const CellCamera& c : cell_.device.cameras) {
        im.eyes.push_back({c.position, c.min_range_m, c.max_range_m, &c});
      }
      im.min_eyes = d.type == DeviceType::kMocap ? d.min_cameras : 1;
    }
    for (const CellTarget& t : cell.targets) {
      double a = t.acceptance_rad;
      if (d.type == DeviceType::kCamera)
        a = std::min(a, d.max_viewing_angle_rad);
      im.acceptance.push_back(a);
    }
  }
  im.distance_request.enable_nearest_points = false;
  return SetParameters(model.nominal, error);
}

bool CellChecker::SetParameters(const Eigen::VectorXd& parameters,
                                std::string* error) {
  std::string why;
  if (!model_.CheckParameters(parameters, &why)) {
    if (error) *error = "cell check parameters: " + why;
    return false;
  }
  impl_->parameters = parameters;
  impl_->blocks = BlockPointers(model_, impl_->parameters.data());
  return true;
}

const Eigen::VectorXd& CellChecker::parameters() const {
  return impl_->parameters;
}

int CellChecker::num_self_pairs() const {
  return static_cast<int>(impl_->self_body_pairs.size());
}

std::unique_ptr<CellChecker::Workspace> CellChecker::NewWorkspace() const {
  std::unique_ptr<Workspace> workspace(new Workspace());
  Workspace::Data* w = workspace->data_.get();
  for (const Impl::Shape& s : impl_->shapes) {
    w->objects.push_back(std::make_unique<fcl::CollisionObjectd>(s.geometry));
  }
  w->frames.resize(model_.num_joints() + 1);
  w->world.resize(impl_->shapes.size());
  w->centres.resize(impl_->shapes.size());
  w->beam = std::make_shared<fcl::Capsuled>(kBeamRadiusM, 1.0);
  w->beam_object = std::make_unique<fcl::CollisionObjectd>(w->beam);
  return workspace;
}

void CellChecker::LinkFrames(const double* q,
                             std::vector<FixedTransform>* frames) const {
  frames->resize(model_.num_joints() + 1);
  (*frames)[0] = FixedTransform();
  Eigen::Matrix3d R;
  Eigen::Vector3d t;
  for (int j = 0; j < model_.num_joints(); ++j) {
    LinkTransform(model_.links[j], impl_->blocks[j + 1], q[j], &R, &t);
    const FixedTransform& prev = (*frames)[j];
    FixedTransform& next = (*frames)[j + 1];
    next.translation = prev.translation + prev.rotation * t;
    next.rotation = prev.rotation * R;
  }
}

FixedTransform CellChecker::TipFrame(const double* q) const {
  std::vector<FixedTransform> frames;
  LinkFrames(q, &frames);
  return Compose(frames.back(), model_.tip);
}

namespace {

// Places every shape of the workspace at the frames.
template <typename Shapes>
void PlaceShapes(const Shapes& shapes, std::vector<FixedTransform>* world,
                 std::vector<Eigen::Vector3d>* centres,
                 std::vector<std::unique_ptr<fcl::CollisionObjectd>>* objects,
                 const std::vector<FixedTransform>& frames) {
  for (size_t i = 0; i < shapes.size(); ++i) {
    const auto& s = shapes[i];
    (*world)[i] = Compose(frames[s.frame], s.in_frame);
    (*centres)[i] =
        (*world)[i].rotation * s.ball_centre + (*world)[i].translation;
    (*objects)[i]->setTransform((*world)[i].rotation, (*world)[i].translation);
  }
}

}  // namespace

PoseVerdict CellChecker::CheckCollisions(const double* q,
                                         Workspace* workspace) const {
  return Collisions(q, workspace, false);
}

PoseVerdict CellChecker::Collisions(const double* q, Workspace* workspace,
                                    bool frames_ready) const {
  Workspace::Data* w = workspace->data_.get();
  const Impl& im = *impl_;
  PoseVerdict v;
  if (im.shapes.empty()) return v;
  if (!frames_ready) LinkFrames(q, &w->frames);
  PlaceShapes(im.shapes, &w->world, &w->centres, &w->objects, w->frames);
  // Self-collision.
  for (const Impl::ShapePair& p : im.self_pairs) {
    const Impl::Shape &a = im.shapes[p.a], &b = im.shapes[p.b];
    const double gap = (w->centres[p.a] - w->centres[p.b]).norm() -
                       a.ball_radius - b.ball_radius;
    if (gap >= cell_.self_clearance_m) continue;
    fcl::DistanceResultd result;
    const double d = fcl::distance(w->objects[p.a].get(), w->objects[p.b].get(),
                                   im.distance_request, result);
    if (d < cell_.self_clearance_m) {
      v.reason = RejectionReason::kSelfCollision;
      v.a = static_cast<int16_t>(std::min(a.body, b.body));
      v.b = static_cast<int16_t>(std::max(a.body, b.body));
      return v;
    }
  }
  // Obstacles.
  for (const Impl::ObstaclePair& p : im.obstacle_pairs) {
    const Obstacle& ob = cell_.obstacles[p.obstacle];
    const Impl::Shape& s = im.shapes[p.shape];
    double d;
    if (ob.plane) {
      const double ball =
          ob.normal.dot(w->centres[p.shape]) - s.ball_radius - ob.offset_m;
      if (ball >= cell_.clearance_m) continue;
      d = LowestAlong(*s.source, w->world[p.shape].rotation,
                      w->world[p.shape].translation, ob.normal) -
          ob.offset_m;
    } else {
      const Impl::SolidObstacle& solid = im.solids[im.solid_of[p.obstacle]];
      const double gap = (w->centres[p.shape] - solid.ball_centre).norm() -
                         s.ball_radius - solid.ball_radius;
      if (gap >= cell_.clearance_m) continue;
      fcl::DistanceResultd result;
      d = fcl::distance(w->objects[p.shape].get(), solid.object.get(),
                        im.distance_request, result);
    }
    if (d < cell_.clearance_m) {
      v.reason = RejectionReason::kObstacle;
      v.a = static_cast<int16_t>(p.obstacle);
      v.b = static_cast<int16_t>(s.body);
      return v;
    }
  }
  return v;
}

PoseVerdict CellChecker::Check(const double* q, Workspace* workspace) const {
  Workspace::Data* w = workspace->data_.get();
  const Impl& im = *impl_;
  PoseVerdict v;
  // 1. Joint margins.
  for (int j = 0; j < model_.num_joints(); ++j) {
    const Link& l = model_.links[j];
    const double m = margins_[j];
    if (q[j] < l.joint_min + m - kJointTolerance ||
        q[j] > l.joint_max - m + kJointTolerance || !std::isfinite(q[j])) {
      v.reason = RejectionReason::kJointMargin;
      v.a = static_cast<int16_t>(j);
      return v;
    }
  }
  // 2-4. Range, view and facing of each target, from the forward
  // kinematics.
  const int num_targets = static_cast<int>(cell_.targets.size());
  const int num_eyes = static_cast<int>(im.eyes.size());
  uint32_t alive_targets = 0;
  // Per target, the eyes still seeing it (bit e).
  uint64_t eyes_of[32] = {};
  Eigen::Vector3d points[32];
  if (num_targets > 0) {
    LinkFrames(q, &w->frames);
    const FixedTransform tip = Compose(w->frames.back(), model_.tip);
    int worst = 0;  // the furthest step at which a target dropped out
    for (int t = 0; t < num_targets; ++t) {
      const CellTarget& target = cell_.targets[t];
      const Eigen::Vector3d p = tip.rotation * target.xyz_m + tip.translation;
      const Eigen::Vector3d n = tip.rotation * target.normal;
      points[t] = p;
      int in_range = 0, in_view = 0, facing = 0;
      uint64_t seeing = 0;
      for (int e = 0; e < num_eyes; ++e) {
        const Impl::Eye& eye = im.eyes[e];
        const Eigen::Vector3d to_eye = eye.position - p;
        const double d = to_eye.norm();
        if (!(d >= eye.min_range && d <= eye.max_range)) continue;
        ++in_range;
        if (eye.camera != nullptr) {
          const CellCamera& c = *eye.camera;
          const Eigen::Vector3d pc = c.rotation.transpose() * (-to_eye);
          if (c.has_intrinsics) {
            if (!(pc.z() > 0)) continue;
            const double u = c.fx * pc.x() / pc.z() + c.cx;
            const double vv = c.fy * pc.y() / pc.z() + c.cy;
            if (!(u >= 0 && u <= c.width && vv >= 0 && vv <= c.height))
              continue;
          } else if (AngleBetween(pc, Eigen::Vector3d::UnitZ()) >
                     c.half_fov_rad + kAngleTolerance) {
            continue;
          }
        }
        ++in_view;
        if (AngleBetween(n, to_eye) > im.acceptance[t] + kAngleTolerance)
          continue;
        ++facing;
        seeing |= uint64_t{1} << e;
      }
      int step = 0;
      if (in_range < im.min_eyes) {
        step = 1;
      } else if (in_view < im.min_eyes) {
        step = 2;
      } else if (facing < im.min_eyes) {
        step = 3;
      }
      if (step == 0) {
        alive_targets |= 1u << t;
        eyes_of[t] = seeing;
      } else {
        worst = std::max(worst, step);
      }
    }
    if (alive_targets == 0) {
      v.reason = worst == 1   ? RejectionReason::kOutOfRange
                 : worst == 2 ? RejectionReason::kOutOfView
                              : RejectionReason::kFacingAway;
      return v;
    }
  }
  // 5-6. Collisions of the robot.
  const PoseVerdict collision = Collisions(q, workspace, num_targets > 0);
  if (!collision.feasible()) return collision;
  if (num_targets == 0) return v;
  // 7. Lines of sight (the shapes are placed by CheckCollisions).
  int first_blocker = 0;
  bool blocked_once = false;
  for (int t = 0; t < num_targets; ++t) {
    if (!(alive_targets & (1u << t))) continue;
    int clear = 0;
    for (int e = 0; e < num_eyes; ++e) {
      if (!(eyes_of[t] & (uint64_t{1} << e))) continue;
      const Eigen::Vector3d& from = im.eyes[e].position;
      const Eigen::Vector3d full = points[t] - from;
      const double length = full.norm() - cell_.line_of_sight_margin_m;
      bool blocked = false;
      int blocker = 0;
      if (length > 0) {
        const Eigen::Vector3d dir = full / full.norm();
        const Eigen::Vector3d to = from + length * dir;
        // Planes: the device is outside, so the beam crosses one when its
        // end is inside.
        for (size_t o = 0; o < cell_.obstacles.size() && !blocked; ++o) {
          const Obstacle& ob = cell_.obstacles[o];
          if (ob.plane && ob.normal.dot(to) < ob.offset_m) {
            blocked = true;
            blocker = -1 - static_cast<int>(o);
          }
        }
        bool placed = false;
        auto place_beam = [&]() {
          if (placed) return;
          placed = true;
          w->beam->lz = length;
          w->beam->computeLocalAABB();
          const Eigen::Vector3d helper = std::abs(dir.x()) < 0.9
                                             ? Eigen::Vector3d::UnitX()
                                             : Eigen::Vector3d::UnitY();
          Eigen::Matrix3d R;
          R.col(0) = helper.cross(dir).normalized();
          R.col(1) = dir.cross(R.col(0));
          R.col(2) = dir;
          w->beam_object->setTransform(R, 0.5 * (from + to));
          w->beam_object->computeAABB();
        };
        for (const Impl::SolidObstacle& s : im.solids) {
          if (blocked) break;
          if (PointSegmentDistance(s.ball_centre, from, to) >
              s.ball_radius + kBeamRadiusM) {
            continue;
          }
          place_beam();
          fcl::CollisionRequestd request;
          fcl::CollisionResultd result;
          if (fcl::collide(w->beam_object.get(), s.object.get(), request,
                           result) > 0) {
            blocked = true;
            blocker = -1 - s.obstacle;
          }
        }
        for (size_t i = 0; i < im.shapes.size() && !blocked; ++i) {
          if (im.shapes[i].mount_of & (1u << t)) continue;
          if (PointSegmentDistance(w->centres[i], from, to) >
              im.shapes[i].ball_radius + kBeamRadiusM) {
            continue;
          }
          place_beam();
          fcl::CollisionRequestd request;
          fcl::CollisionResultd result;
          if (fcl::collide(w->beam_object.get(), w->objects[i].get(), request,
                           result) > 0) {
            blocked = true;
            blocker = im.shapes[i].body;
          }
        }
      }
      if (blocked) {
        if (!blocked_once) first_blocker = blocker;
        blocked_once = true;
      } else {
        ++clear;
      }
    }
    if (clear >= im.min_eyes) v.targets_seen |= 1u << t;
  }
  if (v.targets_seen == 0) {
    v.reason = RejectionReason::kLineOfSight;
    v.a = static_cast<int16_t>(first_blocker);
  }
  return v;
}

std::vector<PairDistance> CellChecker::Distances(const double* q,
                                                 Workspace* workspace) const {
  Workspace::Data* w = workspace->data_.get();
  const Impl& im = *impl_;
  std::vector<PairDistance> out;
  LinkFrames(q, &w->frames);
  PlaceShapes(im.shapes, &w->world, &w->centres, &w->objects, w->frames);
  const double inf = std::numeric_limits<double>::infinity();
  for (const auto& [ba, bb] : im.self_body_pairs) {
    PairDistance pd{robot_.bodies[ba].name, robot_.bodies[bb].name, false, inf};
    for (const Impl::ShapePair& p : im.self_pairs) {
      const int x = std::min(im.shapes[p.a].body, im.shapes[p.b].body);
      const int y = std::max(im.shapes[p.a].body, im.shapes[p.b].body);
      if (x != ba || y != bb) continue;
      fcl::DistanceResultd result;
      pd.distance_m =
          std::min(pd.distance_m,
                   fcl::distance(w->objects[p.a].get(), w->objects[p.b].get(),
                                 im.distance_request, result));
    }
    out.push_back(pd);
  }
  for (const auto& [o, body] : im.obstacle_body_pairs) {
    const Obstacle& ob = cell_.obstacles[o];
    PairDistance pd{robot_.bodies[body].name, ob.name, true, inf};
    for (const Impl::ObstaclePair& p : im.obstacle_pairs) {
      if (p.obstacle != o || im.shapes[p.shape].body != body) continue;
      double d;
      if (ob.plane) {
        d = LowestAlong(*im.shapes[p.shape].source, w->world[p.shape].rotation,
                        w->world[p.shape].translation, ob.normal) -
            ob.offset_m;
      } else {
        fcl::DistanceResultd result;
        d = fcl::distance(w->objects[p.shape].get(),
                          im.solids[im.solid_of[o]].object.get(),
                          im.distance_request, result);
      }
      pd.distance_m = std::min(pd.distance_m, d);
    }
    out.push_back(pd);
  }
  return out;
}

std::string CellChecker::Detail(const PoseVerdict& v) const {
  auto body = [&](int b) {
    return b >= 0 && b < static_cast<int>(robot_.bodies.size())
               ? robot_.bodies[b].name
               : std::string("?");
  };
  switch (v.reason) {
    case RejectionReason::kJointMargin:
      return v.a >= 0 && v.a < model_.num_joints() ? model_.links[v.a].name
                                                   : "?";
    case RejectionReason::kSelfCollision:
      return body(v.a) + "|" + body(v.b);
    case RejectionReason::kObstacle:
      return body(v.b);
    case RejectionReason::kLineOfSight:
      if (v.a < 0) {
        const int o = -1 - v.a;
        return o < static_cast<int>(cell_.obstacles.size())
                   ? cell_.obstacles[o].name
                   : "?";
      }
      return body(v.a);
    default:
      return "";
  }
}

std::string CellChecker::Describe(const PoseVerdict& v) const {
  std::string text = RejectionReasonLabel(v.reason);
  if (v.reason == RejectionReason::kObstacle) {
    const std::string name =
        v.a >= 0 && v.a < static_cast<int>(cell_.obstacles.size())
            ? cell_.obstacles[v.a].name
            : "?";
    return text + " " + name + " (" + Detail(v) + ")";
  }
  std::string detail = Detail(v);
  if (v.reason == RejectionReason::kSelfCollision) {
    detail.replace(detail.find('|'), 1, ", ");
  }
  return detail.empty() ? text : text + " (" + detail + ")";
}

}  // namespace activecal
