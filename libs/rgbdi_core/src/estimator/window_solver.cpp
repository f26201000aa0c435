#include "rgbdi/estimator/window_solver.h"

#include <Eigen/Cholesky>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <stdexcept>
#include <unordered_map>

#include "estimator/dense_kernels.h"
#include "estimator/robust_correction.h"
#include "rgbdi/estimator/marginalization.h"
#include "rgbdi/estimator/pose_manifold.h"

namespace rgbdi::estimator {

std::string WindowSolverOptions::problem() const {
  if (max_iterations < 1) return "max_iterations must be at least 1";
  if (!(function_tolerance >= 0.0) || !(gradient_tolerance >= 0.0) || !(parameter_tolerance >= 0.0))
    return "tolerances must be non-negative";
  if (!(initial_trust_region_radius > 0.0) ||
      !(max_trust_region_radius >= initial_trust_region_radius) ||
      !(min_trust_region_radius >= 0.0))
    return "trust region radii must satisfy 0 < initial <= max";
  if (!(min_relative_decrease > 0.0 && min_relative_decrease < 1.0))
    return "min_relative_decrease must lie in (0, 1)";
  if (!(min_lm_diagonal > 0.0 && max_lm_diagonal >= min_lm_diagonal))
    return "LM diagonal clamp must satisfy 0 < min <= max";
  if (!(max_time_s >= 0.0)) return "max_time_s must be non-negative";
  return {};
}

namespace {

using RowMajor = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;

/// Damping increases (x10 each) tried within one iteration when the system does not factorise.
constexpr int kFactorisationRetries = 8;

/// Where a parameter block of a residual lives in the solver.
struct BlockRef {
  enum Kind : std::uint8_t { kConstant, kFrame, kEliminated } kind = kConstant;
  int index = 0;    ///< frame: column offset in the reduced system; eliminated: its number
  int tangent = 0;  ///< frame: columns
};

}  // namespace

struct WindowSolver::Impl {
  struct FrameBlock {
    double* x;
    int ambient;
    int tangent;
    int offset;
  };
  struct Scalar {
    double* x;
    double lower;
  };
  struct Residual {
    const ceres::CostFunction* cost;
    const ceres::LossFunction* loss;
    int first_block;  ///< into blocks/refs
    int n_blocks;
    int eliminated = -1;        ///< the eliminated scalar it holds, or -1
    int eliminated_block = -1;  ///< which of its blocks that scalar is
  };

  std::vector<FrameBlock> frames;
  std::vector<Scalar> scalars;
  std::unordered_map<const double*, BlockRef> ref_of;
  std::vector<Residual> residuals;
  std::vector<double*> blocks;
  std::vector<BlockRef> refs;
  int nf = 0;  ///< reduced system size

  std::shared_ptr<const MarginalizationInfo> prior;
  std::vector<int> prior_offsets;  ///< per kept block of the prior: its column offset, or -1

  // Linearisation at the current point.
  Eigen::MatrixXd H;                      ///< frame-frame block of J^T J
  Eigen::VectorXd g;                      ///< frame part of J^T r
  Eigen::VectorXd hd;                     ///< eliminated scalars: J^T J
  Eigen::VectorXd gd;                     ///< eliminated scalars: J^T r
  RowMajor coupling;                      ///< row d: J_d^T J_frames of scalar d
  std::vector<std::vector<int>> coupled;  ///< per scalar: the frame blocks it couples with
  // Step.
  Eigen::MatrixXd A;
  Eigen::VectorXd b, dx_f, dx_d, saved;
  Eigen::LLT<Eigen::MatrixXd> llt;
  // Evaluation scratch.
  std::vector<double> jac, res, row;
  std::vector<double*> jac_ptrs;
  const int* cols = nullptr;  ///< the current residual's parameter block sizes

  BlockRef refOf(double* x) const {
    const auto it = ref_of.find(x);
    return it == ref_of.end() ? BlockRef{} : it->second;
  }

  /// Cost at the current values; with `linearise` also H, g, hd, gd, coupling. False when a
  /// residual cannot be evaluated there.
  bool evaluate(bool linearise, double* cost);
  void accumulate(const Residual& r, const double* residual, int n);
  /// Solves the damped system (mu: 1 / trust region radius); false if not positive definite.
  bool solveStep(double mu, const WindowSolverOptions& o);
  /// 1/2 d^T (J^T J) d + g^T d of the step (the model's cost change, negated).
  double modelDecrease() const;
  void saveValues();
  void restoreValues();
  void applyStep();
  double stepNorm() const;
  double valueNorm() const;
};

WindowSolver::WindowSolver() : impl_(std::make_unique<Impl>()) {}
WindowSolver::~WindowSolver() = default;

void WindowSolver::clear() {
  Impl& m = *impl_;
  m.frames.clear();
  m.scalars.clear();
  m.ref_of.clear();
  m.residuals.clear();
  m.blocks.clear();
  m.refs.clear();
  m.nf = 0;
  m.prior.reset();
  m.prior_offsets.clear();
}

void WindowSolver::addFrameBlock(double* x, int ambient_size) {
  Impl& m = *impl_;
  if (ambient_size < 1) throw std::invalid_argument("WindowSolver: block size must be positive");
  if (m.ref_of.count(x)) throw std::invalid_argument("WindowSolver: block added twice");
  const int t = MarginalizationInfo::tangentSize(ambient_size);
  m.ref_of[x] = BlockRef{BlockRef::kFrame, m.nf, t};
  m.frames.push_back({x, ambient_size, t, m.nf});
  m.nf += t;
}

void WindowSolver::addEliminatedScalar(double* x, double lower_bound) {
  Impl& m = *impl_;
  if (m.ref_of.count(x)) throw std::invalid_argument("WindowSolver: block added twice");
  m.ref_of[x] = BlockRef{BlockRef::kEliminated, static_cast<int>(m.scalars.size()), 1};
  m.scalars.push_back({x, lower_bound});
}

void WindowSolver::addResidual(const ceres::CostFunction* cost, const ceres::LossFunction* loss,
                               const std::vector<double*>& blocks) {
  Impl& m = *impl_;
  const auto& sizes = cost->parameter_block_sizes();
  if (sizes.size() != blocks.size())
    throw std::invalid_argument("WindowSolver: residual with a wrong number of blocks");
  Impl::Residual r{cost, loss, static_cast<int>(m.blocks.size()), static_cast<int>(blocks.size())};
  for (std::size_t k = 0; k < blocks.size(); ++k) {
    const BlockRef ref = m.refOf(blocks[k]);
    if (ref.kind == BlockRef::kEliminated) {
      if (r.eliminated >= 0)
        throw std::invalid_argument("WindowSolver: a residual holds two eliminated scalars");
      if (sizes[k] != 1) throw std::invalid_argument("WindowSolver: eliminated block not scalar");
      r.eliminated = ref.index;
      r.eliminated_block = static_cast<int>(k);
    }
    if (ref.kind == BlockRef::kFrame && MarginalizationInfo::tangentSize(sizes[k]) != ref.tangent)
      throw std::invalid_argument("WindowSolver: block size differs from its declaration");
    m.blocks.push_back(blocks[k]);
    m.refs.push_back(ref);
  }
  m.residuals.push_back(r);
}

void WindowSolver::addPrior(std::shared_ptr<const MarginalizationInfo> prior) {
  Impl& m = *impl_;
  m.prior = std::move(prior);
  m.prior_offsets.clear();
  for (std::size_t k = 0; k < m.prior->keptBlocks().size(); ++k) {
    const BlockRef ref = m.refOf(m.prior->keptBlocks()[k]);
    if (ref.kind == BlockRef::kEliminated)
      throw std::invalid_argument("WindowSolver: the prior holds an eliminated scalar");
    m.prior_offsets.push_back(ref.kind == BlockRef::kFrame ? ref.index : -1);
  }
}

void WindowSolver::Impl::accumulate(const Residual& r, const double* residual, int n) {
  // Only H's lower triangle is formed (blocks with row offset >= column offset; the Cholesky
  // factorisation and the products below read that triangle).
  const int d = r.eliminated;
  // The eliminated scalar's Jacobian column (n x 1), if the residual holds one.
  const double* Jd =
      r.eliminated_block >= 0 ? jac_ptrs[static_cast<std::size_t>(r.eliminated_block)] : nullptr;
  if (Jd) {
    double h = 0.0, gg = 0.0;
    for (int i = 0; i < n; ++i) {
      h += Jd[i] * Jd[i];
      gg += Jd[i] * residual[i];
    }
    hd[d] += h;
    gd[d] += gg;
  }
  for (int a = 0; a < r.n_blocks; ++a) {
    const BlockRef& ra = refs[static_cast<std::size_t>(r.first_block + a)];
    if (ra.kind != BlockRef::kFrame) continue;
    const double* Ja = jac_ptrs[static_cast<std::size_t>(a)];
    const int sa = cols[a];
    detail::addJtv(g.data() + ra.index, Ja, sa, ra.tangent, residual, n);
    if (Jd) detail::addJtv(coupling.row(d).data() + ra.index, Ja, sa, ra.tangent, Jd, n);
    for (int c = 0; c < r.n_blocks; ++c) {
      const BlockRef& rc = refs[static_cast<std::size_t>(r.first_block + c)];
      if (rc.kind != BlockRef::kFrame || rc.index > ra.index) continue;
      detail::addJtJ(H.data(), nf, ra.index, rc.index, Ja, sa, ra.tangent,
                     jac_ptrs[static_cast<std::size_t>(c)], cols[c], rc.tangent, n);
    }
  }
}

bool WindowSolver::Impl::evaluate(bool linearise, double* cost) {
  *cost = 0.0;
  const int nd = static_cast<int>(scalars.size());
  if (linearise) {
    H.setZero(nf, nf);
    g.setZero(nf);
    hd.setZero(nd);
    gd.setZero(nd);
    coupling.setZero(nd, nf);
  }
  for (const Residual& r : residuals) {
    const int n = r.cost->num_residuals();
    const auto& sizes = r.cost->parameter_block_sizes();
    cols = sizes.data();
    if (res.size() < static_cast<std::size_t>(n)) res.resize(static_cast<std::size_t>(n));
    double** jp = nullptr;
    if (linearise) {
      std::size_t total = 0;
      for (int k = 0; k < r.n_blocks; ++k) total += static_cast<std::size_t>(n * sizes[k]);
      if (jac.size() < total) jac.resize(total);
      jac_ptrs.resize(static_cast<std::size_t>(r.n_blocks));
      std::size_t off = 0;
      for (int k = 0; k < r.n_blocks; ++k) {
        // Constant blocks get no Jacobian (the cost function skips it).
        const bool wanted =
            refs[static_cast<std::size_t>(r.first_block + k)].kind != BlockRef::kConstant;
        jac_ptrs[static_cast<std::size_t>(k)] = wanted ? jac.data() + off : nullptr;
        off += static_cast<std::size_t>(n * sizes[k]);
      }
      jp = jac_ptrs.data();
    }
    if (!r.cost->Evaluate(blocks.data() + r.first_block, res.data(), jp)) return false;
    if (r.loss) {
      *cost += detail::applyRobustLoss(*r.loss, n, res.data(), jp, cols, r.n_blocks, row);
    } else {
      *cost += 0.5 * Eigen::Map<const Eigen::VectorXd>(res.data(), n).squaredNorm();
    }
    if (!std::isfinite(*cost)) return false;
    if (linearise) accumulate(r, res.data(), n);
  }
  // The prior's J^T J is constant (formed by the marginalisation); only H's lower triangle.
  if (prior)
    *cost += linearise
                 ? prior->addNormalEquations(prior->keptBlocks().data(), prior_offsets, true, H, g)
                 : prior->evaluate(prior->keptBlocks().data());
  return std::isfinite(*cost);
}

bool WindowSolver::Impl::solveStep(double mu, const WindowSolverOptions& o) {
  const int nd = static_cast<int>(scalars.size());
  auto damped = [&](double h) {
    return h + mu * std::clamp(h, o.min_lm_diagonal, o.max_lm_diagonal);
  };
  A = H;
  for (int i = 0; i < nf; ++i) A(i, i) = damped(H(i, i));
  b = -g;
  // Eliminate each scalar: A -= c c^T / a, b += c g_d / a, over the blocks it couples with
  // (lower triangle only).
  double* Ad = A.data();
  for (int d = 0; d < nd; ++d) {
    const double a = damped(hd[d]);
    const double* c = coupling.row(d).data();
    const auto& list = coupled[static_cast<std::size_t>(d)];
    for (int p : list) {
      const FrameBlock& bp = frames[static_cast<std::size_t>(p)];
      for (int i = 0; i < bp.tangent; ++i) b[bp.offset + i] += c[bp.offset + i] * (gd[d] / a);
      for (int q : list) {
        const FrameBlock& bq = frames[static_cast<std::size_t>(q)];
        if (bq.offset > bp.offset) continue;
        detail::subtractOuter(Ad, nf, c, bp.offset, bp.tangent, bq.offset, bq.tangent, a);
      }
    }
  }
  llt.compute(A);
  if (llt.info() != Eigen::Success) return false;
  dx_f = llt.solve(b);
  if (!dx_f.allFinite()) return false;
  dx_d.resize(nd);
  for (int d = 0; d < nd; ++d) dx_d[d] = -(gd[d] + coupling.row(d).dot(dx_f)) / damped(hd[d]);
  return dx_d.allFinite();
}

double WindowSolver::Impl::modelDecrease() const {
  // L(0) - L(d) = -(g^T d + 1/2 d^T H d) over the full system [frames | scalars].
  const int nd = static_cast<int>(scalars.size());
  double quad = dx_f.dot(H.selfadjointView<Eigen::Lower>() * dx_f);
  double lin = g.dot(dx_f);
  for (int d = 0; d < nd; ++d) {
    quad += 2.0 * dx_d[d] * coupling.row(d).dot(dx_f) + hd[d] * dx_d[d] * dx_d[d];
    lin += gd[d] * dx_d[d];
  }
  return -(lin + 0.5 * quad);
}

void WindowSolver::Impl::saveValues() {
  std::size_t n = scalars.size();
  for (const FrameBlock& f : frames) n += static_cast<std::size_t>(f.ambient);
  saved.resize(static_cast<Eigen::Index>(n));
  Eigen::Index k = 0;
  for (const FrameBlock& f : frames)
    for (int i = 0; i < f.ambient; ++i) saved[k++] = f.x[i];
  for (const Scalar& s : scalars) saved[k++] = *s.x;
}

void WindowSolver::Impl::restoreValues() {
  Eigen::Index k = 0;
  for (const FrameBlock& f : frames)
    for (int i = 0; i < f.ambient; ++i) f.x[i] = saved[k++];
  for (const Scalar& s : scalars) *s.x = saved[k++];
}

void WindowSolver::Impl::applyStep() {
  const PoseManifold pose;
  double plus[7];
  for (const FrameBlock& f : frames) {
    const double* delta = dx_f.data() + f.offset;
    if (f.ambient == 7) {
      pose.Plus(f.x, delta, plus);
      std::copy(plus, plus + 7, f.x);
    } else {
      for (int i = 0; i < f.ambient; ++i) f.x[i] += delta[i];
    }
  }
  for (std::size_t d = 0; d < scalars.size(); ++d)
    *scalars[d].x = std::max(scalars[d].lower, *scalars[d].x + dx_d[static_cast<Eigen::Index>(d)]);
}

double WindowSolver::Impl::stepNorm() const {
  return std::sqrt(dx_f.squaredNorm() + dx_d.squaredNorm());
}

double WindowSolver::Impl::valueNorm() const {
  double sq = 0.0;
  for (const FrameBlock& f : frames)
    for (int i = 0; i < f.ambient; ++i) sq += f.x[i] * f.x[i];
  for (const Scalar& s : scalars) sq += *s.x * *s.x;
  return std::sqrt(sq);
}

WindowSolverSummary WindowSolver::solve(const WindowSolverOptions& o) {
  if (const std::string why = o.problem(); !why.empty())
    throw std::invalid_argument("WindowSolverOptions: " + why);
  Impl& m = *impl_;
  using Clock = std::chrono::steady_clock;
  const auto start = Clock::now();
  WindowSolverSummary s;

  // Which frame blocks each scalar couples with (fixed by the residuals' structure).
  m.coupled.assign(m.scalars.size(), {});
  std::vector<int> frame_of_offset(static_cast<std::size_t>(m.nf), -1);
  for (std::size_t k = 0; k < m.frames.size(); ++k)
    frame_of_offset[static_cast<std::size_t>(m.frames[k].offset)] = static_cast<int>(k);
  for (const Impl::Residual& r : m.residuals) {
    if (r.eliminated < 0) continue;
    auto& list = m.coupled[static_cast<std::size_t>(r.eliminated)];
    for (int k = 0; k < r.n_blocks; ++k) {
      const BlockRef& ref = m.refs[static_cast<std::size_t>(r.first_block + k)];
      if (ref.kind != BlockRef::kFrame) continue;
      const int f = frame_of_offset[static_cast<std::size_t>(ref.index)];
      if (std::find(list.begin(), list.end(), f) == list.end()) list.push_back(f);
    }
  }
  for (auto& list : m.coupled) std::sort(list.begin(), list.end());

  double cost = 0.0;
  if (!m.evaluate(true, &cost)) {
    s.message = "the residuals cannot be evaluated at the initial values";
    return s;
  }
  s.initial_cost = s.final_cost = cost;
  auto gradientMax = [&] {
    double mx = m.g.size() ? m.g.cwiseAbs().maxCoeff() : 0.0;
    if (m.gd.size()) mx = std::max(mx, m.gd.cwiseAbs().maxCoeff());
    return mx;
  };
  if (gradientMax() <= o.gradient_tolerance) {
    s.termination = WindowSolverSummary::Termination::kConvergence;
    s.message = "gradient tolerance reached";
    return s;
  }
  double radius = o.initial_trust_region_radius;
  double decrease_factor = 2.0;
  for (int it = 0;; ++it) {
    if (it >= o.max_iterations) {
      s.termination = WindowSolverSummary::Termination::kNoConvergence;
      s.message = "maximum number of iterations reached";
      break;
    }
    if (o.max_time_s > 0.0 &&
        std::chrono::duration<double>(Clock::now() - start).count() >= o.max_time_s) {
      s.termination = WindowSolverSummary::Termination::kNoConvergence;
      s.message = "time budget reached";
      break;
    }
    if (radius < o.min_trust_region_radius) {
      s.termination = WindowSolverSummary::Termination::kConvergence;
      s.message = "trust region radius below its minimum";
      break;
    }
    // A damped system that does not factorise (not positive definite in floating point: a
    // direction with next to no information) is solved again with ten times the damping within
    // the same iteration, as Ceres' dogleg does for its Gauss-Newton step; the radius follows.
    bool solved = m.solveStep(1.0 / radius, o);
    for (int retry = 0; !solved && retry < kFactorisationRetries; ++retry) {
      ++s.factorisation_retries;
      radius /= 10.0;
      solved = m.solveStep(1.0 / radius, o);
    }
    const double model = solved ? m.modelDecrease() : 0.0;
    if (!solved || !(model > 0.0)) {
      ++s.unsuccessful_steps;
      radius /= decrease_factor;
      decrease_factor *= 2.0;
      continue;
    }
    if (m.stepNorm() <= o.parameter_tolerance * (m.valueNorm() + o.parameter_tolerance)) {
      s.termination = WindowSolverSummary::Termination::kConvergence;
      s.message = "parameter tolerance reached";
      break;
    }
    m.saveValues();
    m.applyStep();
    double candidate = 0.0;
    const bool valid = m.evaluate(false, &candidate);
    const double change = cost - candidate;
    const bool small_change = valid && std::abs(change) <= o.function_tolerance * cost;
    if (valid && change / model > o.min_relative_decrease) {
      ++s.successful_steps;
      cost = candidate;
      s.final_cost = cost;
      if (small_change) {
        s.termination = WindowSolverSummary::Termination::kConvergence;
        s.message = "function tolerance reached";
        break;
      }
      const double rho = change / model;
      radius = std::min(o.max_trust_region_radius,
                        radius / std::max(1.0 / 3.0, 1.0 - std::pow(2.0 * rho - 1.0, 3)));
      decrease_factor = 2.0;
      if (it + 1 >= o.max_iterations) {  // no step follows: no linearisation either
        s.termination = WindowSolverSummary::Termination::kNoConvergence;
        s.message = "maximum number of iterations reached";
        break;
      }
      if (!m.evaluate(true, &cost)) {  // cannot happen after a valid cost evaluation
        s.message = "the residuals cannot be linearised at an accepted point";
        return s;
      }
      if (gradientMax() <= o.gradient_tolerance) {
        s.termination = WindowSolverSummary::Termination::kConvergence;
        s.message = "gradient tolerance reached";
        break;
      }
      continue;
    }
    m.restoreValues();
    ++s.unsuccessful_steps;
    if (small_change) {
      s.termination = WindowSolverSummary::Termination::kConvergence;
      s.message = "function tolerance reached";
      break;
    }
    radius /= decrease_factor;
    decrease_factor *= 2.0;
  }
  return s;
}

}  // namespace rgbdi::estimator
