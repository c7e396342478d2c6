#include "plugin/fluid/dense_resistance_fluid.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <stdexcept>

#include "plugin/fluid/rft_drag.h"
#include "plugin/mjcf/spatial_algebra.h"

namespace ipmc {
namespace {

// The secant's tolerance for the joints' motion off it, as a share of its
// reach (docs/FLUIDS.md, "Cost on flexible links": 0.05 at the reach 1e-3
// rad keeps the swim within 0.1 % of the exact evaluation's). The secant
// is used only if it is at most kLongestSecant reaches long (an older
// evaluation left by another branch of the run would make a chord across
// a curve) and at least kShortestSecant of one (a shorter one tells its
// direction, and R's change along it, with too few digits).
constexpr double kOffSecant = 0.05;
constexpr double kLongestSecant = 4.0;
constexpr double kShortestSecant = 0.1;
// The fit's interval grows by at most kFitGrowth per exact evaluation and
// is kFitSafety of what its measured error allows.
constexpr double kFitGrowth = 2.0;
constexpr double kFitSafety = 0.9;

// The polynomial through (x_k, c_k), k = 0 ... p, x_0 = 0, as its
// monomials in x: sum_k weights(d, k) c_k is the coefficient of x^d.
// Newton's divided differences, then its Horner form P = d_p, P <- P (x -
// x_k) + d_k for k = p - 1 ... 0 multiplied out, on the unit values (the
// coefficients are linear in the c_k).
template <size_t Points>
Eigen::Matrix<double, Points, Points> InterpolatingMonomialWeights(
    const std::array<double, Points>& x) {
  using Weights = Eigen::Matrix<double, Points, Points>;
  const int p = static_cast<int>(Points) - 1;
  Weights c = Weights::Identity();  // row k: the value c_k in the unit values
  for (int level = 1; level <= p; ++level) {
    for (int k = p; k >= level; --k) {
      c.row(k) = (c.row(k) - c.row(k - 1)) / (x[k] - x[k - level]);
    }
  }
  Weights monomials = Weights::Zero();
  monomials.row(0) = c.row(p);
  for (int k = p - 1, degree = 0; k >= 0; --k, ++degree) {
    monomials.row(degree + 1) = monomials.row(degree);
    for (int i = degree; i >= 1; --i) {
      monomials.row(i) = monomials.row(i - 1) - x[k] * monomials.row(i);
    }
    monomials.row(0) = c.row(k) - x[k] * monomials.row(0);
  }
  return monomials;
}

// Whether every joint of d moves its bodies in the x-y plane: hinges
// about +-z, slides along it, exactly (so they stay so; the Stokes step's
// planar motions).
bool PlanarJoints(const mjModel* m, const mjData* d) {
  for (int j = 0; j < m->njnt; ++j) {
    const mjtNum* axis = d->xaxis + 3 * j;
    const bool planar = m->jnt_type[j] == mjJNT_HINGE   ? axis[0] == 0 && axis[1] == 0
                        : m->jnt_type[j] == mjJNT_SLIDE ? axis[2] == 0
                                                        : false;
    if (!planar) return false;
  }
  return true;
}

// The last dof of body b's chain (its own or its nearest moving
// ancestor's), -1 if it is fixed to the world.
int LastDof(const mjModel* m, int body) {
  while (body > 0 && m->body_dofnum[body] == 0) body = m->body_parentid[body];
  return body > 0 ? m->body_dofadr[body] + m->body_dofnum[body] - 1 : -1;
}

}  // namespace

CacheParameters::CacheParameters(const std::string& model, const std::string& resistance,
                                 const std::string& section)
    : tolerance_key_(model + "_shape_tolerance_rad"),
      tolerance_field_("ipmc_fluid_" + tolerance_key_),
      tolerance_meaning_(static_cast<char>(std::toupper(resistance.front())) +
                         resistance.substr(1) +
                         " is computed afresh when a joint is more than this off the fit in "
                         "time's cubic through the last exact shapes, or without the fit when "
                         "a joint has moved more than this since it was last computed or off "
                         "the secant of the last two (0: every evaluation; docs/FLUIDS.md, \"" +
                         section + "\")"),
      reach_key_(model + "_secant_reach_rad"),
      reach_field_("ipmc_fluid_" + reach_key_),
      reach_meaning_("Between exact evaluations " + resistance +
                     " is extrapolated along the secant of the last two while no joint has "
                     "moved more than this (0: the last one as it is; docs/FLUIDS.md, \"Cost "
                     "on flexible links\")"),
      fit_key_(model + "_fit_tolerance"),
      fit_field_("ipmc_fluid_" + fit_key_),
      fit_meaning_("Between exact evaluations " + resistance +
                   " follows the cubic in time through the last four, over an interval "
                   "that keeps its error, measured at each exact evaluation against the largest "
                   "translational entry, within this (0: no fit; docs/FLUIDS.md, \"Cost on "
                   "flexible links\")") {}

FluidParameter CacheParameters::ShapeToleranceRad() const {
  return NumberParameter(tolerance_key_.c_str(), tolerance_field_.c_str(), "rad", 1.0, 1e-3,
                         "1e-3", 0.0, true, 2e-3, tolerance_meaning_.c_str());
}

FluidParameter CacheParameters::SecantReachRad() const {
  return NumberParameter(reach_key_.c_str(), reach_field_.c_str(), "rad", 1.0,
                         kDefaultSecantReachRad, "0", 0.0, true, 2e-3, reach_meaning_.c_str());
}

FluidParameter CacheParameters::FitTolerance() const {
  return NumberParameter(fit_key_.c_str(), fit_field_.c_str(), "", 1.0, kDefaultFitTolerance,
                         "1e-4", 0.0, true, 3e-5, fit_meaning_.c_str());
}

DenseResistanceFluid::~DenseResistanceFluid() = default;

DenseResistanceFluid::DenseResistanceFluid(const mjModel* m, const RftDrag& segments,
                                           const std::string& name)
    : rft_(std::make_unique<const RftDrag>(segments)) {
  for (int g : rft_->geom_ids()) {
    const int body = m->geom_bodyid[g];
    auto it = std::find(bodies_.begin(), bodies_.end(), body);
    body_of_geom_.push_back(static_cast<int>(it - bodies_.begin()));
    if (it == bodies_.end()) bodies_.push_back(body);
  }
  if (bodies_.empty()) throw std::invalid_argument(name + ": the model has no segments");
  root_body_ = m->body_rootid[bodies_[0]];
  for (int body : bodies_) {
    if (m->body_rootid[body] != root_body_) {
      throw std::invalid_argument(name + ": the segments must be on one tree of bodies");
    }
  }
  for (int j = 0; j < m->njnt; ++j) {
    const int type = m->jnt_type[j];
    if (m->jnt_bodyid[j] == root_body_) continue;
    if (type != mjJNT_HINGE && type != mjJNT_SLIDE) {
      throw std::invalid_argument(name + ": only hinge and slide joints below the root");
    }
    shape_joints_.push_back(m->jnt_qposadr[j]);
  }
  for (double length_m : rft_->SegmentLengths_m()) body_length_m_ += length_m;
}

void DenseResistanceFluid::Shape(const mjData* d, std::vector<double>* shape) const {
  shape->resize(shape_joints_.size());
  for (size_t k = 0; k < shape_joints_.size(); ++k) (*shape)[k] = d->qpos[shape_joints_[k]];
}

Eigen::MatrixXd DenseResistanceFluid::ComputeInPlaneResistance(const mjModel* m, const mjData* d,
                                                               const Eigen::Vector3d& origin_W,
                                                               bool* out_of_plane_left_out) const {
  *out_of_plane_left_out = false;
  return ComputeResistance(m, d, origin_W);
}

void DenseResistanceFluid::Recompute(const mjModel* m, const mjData* d) const {
  const Eigen::Vector3d origin(d->xpos + 3 * root_body_);
  bool left_out = false;
  const Eigen::MatrixXd world = in_plane_when_planar() && PlanarJoints(m, d)
                                    ? ComputeInPlaneResistance(m, d, origin, &left_out)
                                    : ComputeResistance(m, d, origin);
  // Into the root's frame: R_root = Q6^T R Q6, Q6 = diag(Q, Q, ...),
  // block by block.
  const int n = static_cast<int>(world.rows()) / 3;
  const Eigen::Matrix3d q = BodyRotation(d, root_body_);
  // The oldest exact evaluation's storage takes the new one, in front.
  std::rotate(exact_.begin(), exact_.end() - 1, exact_.end());
  Exact& newest = exact_.front();
  newest.root_resistance.resize(3 * n, 3 * n);
  for (int i = 0; i < n; ++i) {
    for (int j = 0; j < n; ++j) {
      newest.root_resistance.block<3, 3>(3 * i, 3 * j).noalias() =
          q.transpose() * world.block<3, 3>(3 * i, 3 * j) * q;
    }
  }
  if (left_out || Fitting()) LocalPart(m, d, &local_part_);
  if (left_out) FillOutOfPlane(local_part_, &newest.root_resistance);
  root_resistance_ = newest.root_resistance;
  // With the fit, what is fitted in time is R less its local part.
  if (Fitting()) AddLocalPart(local_part_, -1.0, &newest.root_resistance);
  // The fit (still through the evaluations before) against the new one.
  if (fit_ready_) UpdateFitInterval(d->time, newest.root_resistance, root_resistance_);
  newest.time_s = d->time;
  Shape(d, &newest.shape);
  BuildFit();
  extrapolated_ = false;
  root_is_fit_ = root_stale_ = false;
  ++root_version_;
  ++recomputations_;
}

bool DenseResistanceFluid::Extrapolate(const std::vector<double>& shape) const {
  const Exact& newest = exact_[0];
  const Exact& older = exact_[1];
  if (older.shape.size() != shape.size()) return false;
  const int n = static_cast<int>(shape.size());
  const Eigen::Map<const Eigen::VectorXd> q(shape.data(), n), q_b(newest.shape.data(), n),
      q_a(older.shape.data(), n);
  const Eigen::VectorXd step = q - q_b, secant = q_b - q_a;
  const double reach = secant_reach_rad();
  const double secant_length = secant.lpNorm<Eigen::Infinity>();
  if (step.lpNorm<Eigen::Infinity>() > reach || secant_length > kLongestSecant * reach ||
      secant_length < kShortestSecant * reach) {
    return false;
  }
  const double alpha = step.dot(secant) / secant.squaredNorm();
  if ((step - alpha * secant).lpNorm<Eigen::Infinity>() > kOffSecant * reach) return false;
  root_resistance_ = newest.root_resistance;
  root_resistance_ += alpha * (newest.root_resistance - older.root_resistance);
  extrapolated_ = true;
  root_is_fit_ = root_stale_ = false;
  ++root_version_;
  ++extrapolations_;
  return true;
}

void DenseResistanceFluid::BuildFit() const {
  const bool was_ready = fit_ready_;
  fit_ready_ = false;
  if (fit_tolerance() <= 0.0) return;
  const size_t joints = exact_[0].shape.size();
  for (int k = 1; k < kFitPoints; ++k) {
    if (exact_[k].shape.size() != joints || !(exact_[k - 1].time_s > exact_[k].time_s)) return;
  }
  std::array<double, kFitPoints> x;
  for (int k = 0; k < kFitPoints; ++k) x[k] = exact_[k].time_s - exact_[0].time_s;
  const Eigen::Matrix4d weights = InterpolatingMonomialWeights(x);
  const auto shape = [&](int k) {
    return Eigen::Map<const Eigen::VectorXd>(exact_[k].shape.data(),
                                             static_cast<Eigen::Index>(joints));
  };
  static_assert(kFitPoints == 4, "the cubic's four points");
  for (int degree = 0; degree < kFitPoints; ++degree) {
    const auto w = weights.row(degree);
    fit_[degree] = w(0) * exact_[0].root_resistance + w(1) * exact_[1].root_resistance +
                   w(2) * exact_[2].root_resistance + w(3) * exact_[3].root_resistance;
    shape_fit_[degree] = w(0) * shape(0) + w(1) * shape(1) + w(2) * shape(2) + w(3) * shape(3);
  }
  fit_time_s_ = exact_[0].time_s;
  if (!was_ready) fit_interval_s_ = exact_[0].time_s - exact_[1].time_s;
  fit_ready_ = true;
  ++fit_version_;
}

template <typename Value>
void DenseResistanceFluid::FitAt(const std::array<Value, kFitPoints>& fit, double tau_s,
                                 Value* value) {
  static_assert(kFitPoints == 4, "the cubic's four terms");
  *value = fit[0] + tau_s * fit[1] + (tau_s * tau_s) * fit[2] + (tau_s * tau_s * tau_s) * fit[3];
}

void DenseResistanceFluid::UpdateFitInterval(double time_s, const Eigen::MatrixXd& exact,
                                             const Eigen::MatrixXd& resistance) const {
  const double tau_s = time_s - fit_time_s_;
  if (!(tau_s > 0.0)) return;
  // Each entry against R's largest translational diagonal entry T, times
  // the body's length L for each rotation: the error of the force (N) and
  // torque (N m / L) on velocities up to 1 m/s over the body.
  double largest = 0.0;
  for (int i = 3; i < resistance.rows(); i += 6) {
    for (int k = 0; k < 3; ++k) largest = std::max(largest, resistance(i + k, i + k));
  }
  if (!(largest > 0.0)) return;
  Eigen::MatrixXd fit;
  FitAt(fit_, tau_s, &fit);
  double error = 0.0;
  for (int j = 0; j < exact.cols(); ++j) {
    const double scale_j = j % 6 < 3 ? body_length_m_ : 1.0;
    for (int i = 0; i < exact.rows(); ++i) {
      const double scale = scale_j * (i % 6 < 3 ? body_length_m_ : 1.0);
      error = std::max(error, std::abs(fit(i, j) - exact(i, j)) / scale);
    }
  }
  error /= largest;
  last_fit_error_ = error;
  const double grown = kFitGrowth * std::max(fit_interval_s_, tau_s);
  fit_interval_s_ =
      error > 0.0 ? std::min(grown, kFitSafety * tau_s *
                                        std::pow(fit_tolerance() / error, 1.0 / kFitPoints))
                  : grown;
}

bool DenseResistanceFluid::Fitting() const {
  return shape_tolerance_rad() > 0.0 && fit_tolerance() > 0.0;
}

void DenseResistanceFluid::LocalPart(const mjModel* m, const mjData* d,
                                     std::vector<Matrix6>* local) const {
  const Eigen::Matrix3d q = BodyRotation(d, root_body_);
  const Eigen::Vector3d origin(d->xpos + 3 * root_body_);
  const std::vector<Segment> segments = rft_->Segments(m, d);
  local->assign(bodies_.size(), Matrix6::Zero());
  for (size_t i = 0; i < segments.size(); ++i) {
    (*local)[body_of_geom_[i]] += SegmentResistance(
        q.transpose() * (segments[i].center_W - origin), q.transpose() * segments[i].tangent_W,
        segments[i].length_m, Eigen::Vector3d::Zero(), rft_->segment_coefficients()[i]);
  }
}

void DenseResistanceFluid::FillOutOfPlane(const std::vector<Matrix6>& local,
                                          Eigen::MatrixXd* root_resistance) {
  const auto out_of_plane = [](Eigen::Index i) { return i % 6 < 2 || i % 6 == 5; };
  for (Eigen::Index j = 0; j < root_resistance->cols(); ++j) {
    for (Eigen::Index i = 0; i < root_resistance->rows(); ++i) {
      if (!out_of_plane(i) && !out_of_plane(j)) continue;
      (*root_resistance)(i, j) = i / 6 == j / 6 ? local[i / 6](i % 6, j % 6) : 0.0;
    }
  }
}

void DenseResistanceFluid::AddLocalPart(const std::vector<Matrix6>& local, double weight,
                                        Eigen::MatrixXd* resistance) {
  for (size_t b = 0; b < local.size(); ++b) {
    resistance->block<6, 6>(6 * b, 6 * b) += weight * local[b];
  }
}

bool DenseResistanceFluid::Fit(const mjModel* m, const mjData* d,
                               const std::vector<double>& shape) const {
  const double time_s = d->time;
  const double tau_s = time_s - fit_time_s_;
  if (!(tau_s >= 0.0) || tau_s > fit_interval_s_) return false;
  const int joints = static_cast<int>(shape.size());
  const Eigen::Map<const Eigen::VectorXd> q(shape.data(), joints);
  FitAt(shape_fit_, tau_s, &fit_shape_);
  if (joints > 0 && (q - fit_shape_).lpNorm<Eigen::Infinity>() > shape_tolerance_rad()) {
    return false;
  }
  root_is_fit_ = root_stale_ = true;
  root_fit_tau_s_ = tau_s;
  LocalPart(m, d, &local_part_);
  extrapolated_ = true;
  ++root_version_;
  ++fits_;
  return true;
}

const Eigen::MatrixXd* DenseResistanceFluid::InteractionResistance(const mjModel* m,
                                                                   const mjData* d) const {
  UpdateRootResistance(m, d);
  return &WorldResistance(d);
}

// R_c = T^T Q6 R_root Q6^T T (WorldResistance), so G = Q^T T:
// [Q^T 0; Q^T X Q^T] with X = -[r]x.
const Eigen::MatrixXd* DenseResistanceFluid::FrameResistance(const mjModel* m, const mjData* d,
                                                             Eigen::Matrix<double, 6, 6>* frame,
                                                             long* version) const {
  UpdateRootResistance(m, d);
  RootFrame(d, frame);
  *version = root_version_;
  return &RootResistance();
}

bool DenseResistanceFluid::FrameResistanceCubic(const mjModel* m, const mjData* d,
                                                Eigen::Matrix<double, 6, 6>* frame,
                                                ResistanceCubic* cubic) const {
  UpdateRootResistance(m, d);
  if (!root_is_fit_) return false;
  RootFrame(d, frame);
  cubic->coefficients = &fit_;
  cubic->tau_s = root_fit_tau_s_;
  cubic->version = fit_version_;
  cubic->local = &local_part_;
  return true;
}

void DenseResistanceFluid::RootFrame(const mjData* d, Eigen::Matrix<double, 6, 6>* frame) const {
  const Eigen::Matrix3d q = RootRotation(d);
  const Eigen::Matrix3d x = -CrossMatrix(RootOffset(d));
  frame->topLeftCorner<3, 3>() = q.transpose();
  frame->topRightCorner<3, 3>().setZero();
  frame->bottomLeftCorner<3, 3>() = q.transpose() * x;
  frame->bottomRightCorner<3, 3>() = q.transpose();
}

const Eigen::MatrixXd& DenseResistanceFluid::RootResistance() const {
  if (root_stale_) {
    FitAt(fit_, root_fit_tau_s_, &root_resistance_);
    AddLocalPart(local_part_, 1.0, &root_resistance_);
    root_stale_ = false;
  }
  return root_resistance_;
}

Eigen::Matrix3d DenseResistanceFluid::RootRotation(const mjData* d) const {
  return BodyRotation(d, root_body_);
}

Eigen::Vector3d DenseResistanceFluid::RootOffset(const mjData* d) const {
  return Eigen::Vector3d(d->xpos + 3 * root_body_) -
         Eigen::Vector3d(d->subtree_com + 3 * root_body_);
}

void DenseResistanceFluid::UpdateRootResistance(const mjModel* m, const mjData* d) const {
  Shape(d, &shape_);
  if (shape_ == used_shape_ && used_of_recomputation_ == recomputations_) {
    return;  // the same shape again: the same R
  }
  const std::vector<double>& newest = exact_.front().shape;
  // A body without joints below its root has an empty shape: computed once.
  const bool cached = recomputations_ > 0 && newest.size() == shape_.size();
  double farthest = 0.0;
  for (size_t k = 0; cached && k < shape_.size(); ++k) {
    farthest = std::max(farthest, std::abs(shape_[k] - newest[k]));
  }
  const bool secant = shape_tolerance_rad() > 0.0 && secant_reach_rad() > 0.0;
  if (!cached) {
    Recompute(m, d);
  } else if (Fitting()) {
    // Every evaluation exact until the fit has its points (the cached
    // resistance's lag would stay in the run).
    if (!fit_ready_ || !Fit(m, d, shape_)) Recompute(m, d);
  } else if (secant && Extrapolate(shape_)) {
    // the exact evaluations' fit
  } else if (farthest > shape_tolerance_rad()) {
    Recompute(m, d);
  } else if (extrapolated_) {
    root_resistance_ = exact_.front().root_resistance;  // instead of the fit's last
    extrapolated_ = false;
    root_is_fit_ = root_stale_ = false;
    ++root_version_;
  }
  used_shape_ = shape_;
  used_of_recomputation_ = recomputations_;
}

const Eigen::MatrixXd& DenseResistanceFluid::WorldResistance(const mjData* d) const {
  // Back into the world and from the root's origin p to the subtree centre
  // of mass c: V_p = T V_c with T = [I 0; -[p - c]x I], so R_c = T^T R_p T
  // block by block.
  const Eigen::Matrix3d q = RootRotation(d);
  const Eigen::Vector3d r = RootOffset(d);
  if (world_of_version_ == root_version_ && world_rotation_ == q && world_offset_ == r) {
    return world_resistance_;
  }
  world_of_version_ = root_version_;
  world_rotation_ = q;
  world_offset_ = r;
  // Block (i, j) = [C00 C01; C10 C11] with C_kl = Q B_kl Q^T from the root
  // frame's B, then T^T C T with X = -[r]x:
  //   [C00 + C01 X + X^T (C10 + C11 X), C01 + X^T C11; C10 + C11 X, C11].
  // R is symmetric (ComputeResistance), so block (j, i) is (i, j)^T.
  const Eigen::Matrix3d x = -CrossMatrix(r);
  const int bodies = body_count();
  const Eigen::MatrixXd& root = RootResistance();
  world_resistance_.resize(6 * bodies, 6 * bodies);
  for (int i = 0; i < bodies; ++i) {
    for (int j = i; j < bodies; ++j) {
      const auto b = root.block<6, 6>(6 * i, 6 * j);
      const Eigen::Matrix3d c00 = q * b.block<3, 3>(0, 0) * q.transpose();
      const Eigen::Matrix3d c01 = q * b.block<3, 3>(0, 3) * q.transpose();
      const Eigen::Matrix3d c10 = q * b.block<3, 3>(3, 0) * q.transpose();
      const Eigen::Matrix3d c11 = q * b.block<3, 3>(3, 3) * q.transpose();
      const Eigen::Matrix3d lower_left = c10 + c11 * x;
      Matrix6 block;
      block << c00 + c01 * x + x.transpose() * lower_left, c01 + x.transpose() * c11, lower_left,
          c11;
      world_resistance_.block<6, 6>(6 * i, 6 * j) = block;
      if (j != i) world_resistance_.block<6, 6>(6 * j, 6 * i) = block.transpose();
    }
  }
  return world_resistance_;
}

Eigen::VectorXd DenseResistanceFluid::BodyVelocities(const mjData* d) const {
  Eigen::VectorXd v(6 * bodies_.size());
  for (size_t i = 0; i < bodies_.size(); ++i) {
    v.segment<6>(6 * i) = Eigen::Map<const Vector6>(d->cvel + 6 * bodies_[i]);
  }
  return v;
}

void DenseResistanceFluid::AddBodyWrenches(const mjModel* m, const mjData* d,
                                           const Eigen::VectorXd& wrench, mjtNum* qfrc) const {
  for (size_t i = 0; i < bodies_.size(); ++i) {
    const Vector6 w = wrench.segment<6>(6 * i);
    for (int j = LastDof(m, bodies_[i]); j >= 0; j = m->dof_parentid[j]) {
      qfrc[j] += Eigen::Map<const Vector6>(d->cdof + 6 * j).dot(w);
    }
  }
}

void DenseResistanceFluid::Apply(const mjModel* m, mjData* d) const {
  const Eigen::VectorXd wrench = -(*InteractionResistance(m, d) * BodyVelocities(d));
  AddBodyWrenches(m, d, wrench, d->qfrc_passive);
}

double DenseResistanceFluid::DissipatedPower_W(const mjModel* m, const mjData* d) const {
  // The resistance the drag was last applied with: measuring the power
  // must not refresh the cache (after a step d's positions are the next
  // step's while its kinematics are still this one's).
  if (exact_.front().root_resistance.size() == 0) Recompute(m, d);
  const Eigen::VectorXd v = BodyVelocities(d);
  return v.dot(WorldResistance(d) * v);
}

std::vector<double> DenseResistanceFluid::SegmentLengths_m() const {
  return rft_->SegmentLengths_m();
}

double DenseResistanceFluid::Viscosity_Pa_s() const { return rft_->Viscosity_Pa_s(); }

double DenseResistanceFluid::FluidDensity_kg_m3() const { return rft_->FluidDensity_kg_m3(); }

double DenseResistanceFluid::RotationalDragScale_N_m_s() const {
  return rft_->RotationalDragScale_N_m_s();
}

}  // namespace ipmc
