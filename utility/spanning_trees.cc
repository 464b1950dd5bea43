#include "utility/spanning_trees.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <limits>
#include <optional>
#include <unordered_map>
#include <utility>

#include <cholmod.h>
#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>

namespace aslam {
namespace {

constexpr double kEigenvalueFloor =
    1e-8;  // docs/architecture.md §5: smaller eigenvalues are skipped

[[noreturn]] void Fail(const char* what) {
  std::fprintf(stderr, "spanning_trees: %s\n", what);
  std::abort();
}

void CheckEdge(const WeightedEdge& edge, int num_nodes) {
  if (edge.from < 0 || edge.to < 0 || edge.from >= num_nodes || edge.to >= num_nodes) {
    Fail("edge endpoint out of range");
  }
  if (!std::isfinite(edge.weight) || edge.weight < 0.0) Fail("edge weight negative or not finite");
}

// Calls `add(row, col, value)` with the reduced Laplacian's entries (node k -> row k-1;
// node 0 dropped), upper triangle only (row <= col); duplicates are meant to be summed.
template <typename Add>
void ForEachReducedLaplacianEntry(const WeightedGraph& base, const GraphExtension& extension,
                                  Add add) {
  const int num_nodes = base.num_nodes + extension.num_new_nodes;
  auto visit = [&](const WeightedEdge& edge) {
    CheckEdge(edge, num_nodes);
    if (edge.from == edge.to) return;  // a self-loop is not in the Laplacian
    const int a = edge.from - 1;
    const int b = edge.to - 1;
    if (a >= 0) add(a, a, edge.weight);
    if (b >= 0) add(b, b, edge.weight);
    if (a >= 0 && b >= 0) add(std::min(a, b), std::max(a, b), -edge.weight);
  };
  for (const WeightedEdge& edge : base.edges) visit(edge);
  for (const WeightedEdge& edge : extension.edges) visit(edge);
}

// A cholmod_common set up the same way everywhere: AMD only (deterministic and
// cheap on these very sparse graphs), simplicial LDLᵀ (the incremental path
// solves read its columns directly), quiet (we check status).
struct Cholmod {
  cholmod_common common;
  Cholmod() {
    cholmod_start(&common);
    common.nmethods = 1;
    common.method[0].ordering = CHOLMOD_AMD;
    common.postorder = true;
    common.supernodal = CHOLMOD_SIMPLICIAL;
    common.final_ll = false;
    common.print = 0;
  }
  ~Cholmod() { cholmod_finish(&common); }
  Cholmod(const Cholmod&) = delete;
  Cholmod& operator=(const Cholmod&) = delete;
};

cholmod_sparse* BuildReducedLaplacian(const WeightedGraph& base, const GraphExtension& extension,
                                      cholmod_common* common) {
  const int n = base.num_nodes + extension.num_new_nodes - 1;
  const std::size_t max_entries = 3 * (base.edges.size() + extension.edges.size()) + 1;
  cholmod_triplet* triplet =
      cholmod_allocate_triplet(n, n, max_entries, /*stype=*/1, CHOLMOD_REAL, common);
  if (triplet == nullptr) Fail("cholmod_allocate_triplet failed");
  auto* rows = static_cast<int*>(triplet->i);
  auto* cols = static_cast<int*>(triplet->j);
  auto* values = static_cast<double*>(triplet->x);
  std::size_t count = 0;
  ForEachReducedLaplacianEntry(base, extension, [&](int row, int col, double value) {
    rows[count] = row;
    cols[count] = col;
    values[count] = value;
    ++count;
  });
  triplet->nnz = count;
  // Duplicates are summed here, so parallel edges add.
  cholmod_sparse* matrix = cholmod_triplet_to_sparse(triplet, count, common);
  cholmod_free_triplet(&triplet, common);
  if (matrix == nullptr) Fail("cholmod_triplet_to_sparse failed");
  return matrix;
}

// log det of the factored matrix: Σ log D (simplicial LDLᵀ) or 2 Σ log diag(L) (LLᵀ).
double LogDetOfFactor(const cholmod_factor* factor) {
  const auto* x = static_cast<const double*>(factor->x);
  double log_det = 0.0;
  if (factor->is_super) {
    const auto* super = static_cast<const int*>(factor->super);
    const auto* pi = static_cast<const int*>(factor->pi);
    const auto* px = static_cast<const int*>(factor->px);
    for (std::size_t s = 0; s < factor->nsuper; ++s) {
      const int num_cols = super[s + 1] - super[s];
      const int num_rows = pi[s + 1] - pi[s];
      for (int j = 0; j < num_cols; ++j) log_det += 2.0 * std::log(x[px[s] + j + j * num_rows]);
    }
    return log_det;
  }
  const auto* p = static_cast<const int*>(factor->p);
  const double scale = factor->is_ll ? 2.0 : 1.0;
  for (std::size_t j = 0; j < factor->n; ++j) log_det += scale * std::log(x[p[j]]);
  return log_det;
}

// det(a)^(1/3) when every eigenvalue of the symmetric `a` clearly exceeds kEigenvalueFloor,
// which positive LDLᵀ pivots of a - shift·I show (Sylvester): then exp((1/3)·Σ log λ_k) is
// the cube root of the determinant, no eigensolver needed. nullopt near or below the floor;
// the shift's 1e-12·trace outweighs the pivots' rounding.
std::optional<double> CubeRootOfDeterminantIfClearlyDefinite(const Eigen::Matrix3d& a) {
  const double shift = 2.0 * kEigenvalueFloor + 1e-12 * std::abs(a.trace());
  // LDLᵀ of a - shift·I, by hand (3x3): pivots d0, d1, d2.
  const double d0 = a(0, 0) - shift;
  if (!(d0 > 0.0)) return std::nullopt;
  const double l10 = a(1, 0) / d0, l20 = a(2, 0) / d0;
  const double d1 = a(1, 1) - shift - l10 * a(1, 0);
  if (!(d1 > 0.0)) return std::nullopt;
  const double l21 = (a(2, 1) - l20 * a(1, 0)) / d1;
  const double d2 = a(2, 2) - shift - l20 * a(2, 0) - l21 * l21 * d1;
  if (!(d2 > 0.0)) return std::nullopt;
  // The determinant from a's own pivots: a product of positives, no cancellation.
  const double e0 = a(0, 0);
  const double m10 = a(1, 0) / e0, m20 = a(2, 0) / e0;
  const double e1 = a(1, 1) - m10 * a(1, 0);
  const double m21 = (a(2, 1) - m20 * a(1, 0)) / e1;
  const double e2 = a(2, 2) - m20 * a(2, 0) - m21 * m21 * e1;
  return std::cbrt(e0 * e1 * e2);
}

}  // namespace

double DOptimality(const Eigen::Matrix3d& information) {
  // docs/architecture.md §5 (and the AGS authors' code): exp((1/3)·Σ log λ_k) over λ_k > 1e-8,
  // i.e. skipped eigenvalues still count in the 1/3.
  const Eigen::Matrix3d symmetric = 0.5 * (information + information.transpose());
  // Edge information is positive definite in practice: the eigensolver only near the floor.
  if (const std::optional<double> fast = CubeRootOfDeterminantIfClearlyDefinite(symmetric)) {
    return *fast;
  }
  const Eigen::Vector3d eigenvalues =
      Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d>(symmetric, Eigen::EigenvaluesOnly)
          .eigenvalues();
  double sum_log = 0.0;
  int used = 0;
  for (int k = 0; k < 3; ++k) {
    if (eigenvalues[k] > kEigenvalueFloor) {
      sum_log += std::log(eigenvalues[k]);
      ++used;
    }
  }
  if (used == 0) return 0.0;
  return std::exp(sum_log / 3.0);
}

double EOptimality(const Eigen::Matrix3d& information) {
  const Eigen::Matrix3d symmetric = 0.5 * (information + information.transpose());
  return Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d>(symmetric, Eigen::EigenvaluesOnly)
      .eigenvalues()
      .minCoeff();
}

WeightedGraph ToWeightedGraph(const PoseGraph& graph) {
  WeightedGraph weighted;
  weighted.num_nodes = static_cast<int>(graph.nodes.size());
  weighted.edges.reserve(graph.edges.size());
  for (const PoseGraphEdge& edge : graph.edges) {
    if (edge.from_id < 0 || edge.to_id < 0 || edge.from_id >= weighted.num_nodes ||
        edge.to_id >= weighted.num_nodes) {
      Fail("pose graph edge refers to a missing node");
    }
    weighted.edges.push_back({edge.from_id, edge.to_id, DOptimality(edge.information)});
  }
  return weighted;
}

double LogDetReducedLaplacianDense(const WeightedGraph& base, const GraphExtension& extension) {
  const int n = base.num_nodes + extension.num_new_nodes - 1;
  if (n < 0) Fail("log det of an empty graph");
  if (n == 0) return 0.0;  // one vertex: one (empty) spanning tree
  Eigen::MatrixXd laplacian = Eigen::MatrixXd::Zero(n, n);
  ForEachReducedLaplacianEntry(base, extension, [&](int row, int col, double value) {
    laplacian(row, col) += value;
    if (row != col) laplacian(col, row) += value;
  });
  const Eigen::LLT<Eigen::MatrixXd> llt(laplacian);
  // Not positive definite: the graph is disconnected, no spanning tree.
  if (llt.info() != Eigen::Success) return -std::numeric_limits<double>::infinity();
  return 2.0 * llt.matrixLLT().diagonal().array().log().sum();
}

double LogDetReducedLaplacianSparse(const WeightedGraph& base, const GraphExtension& extension) {
  const int n = base.num_nodes + extension.num_new_nodes - 1;
  if (n < 0) Fail("log det of an empty graph");
  if (n == 0) return 0.0;
  Cholmod cholmod;
  cholmod_sparse* matrix = BuildReducedLaplacian(base, extension, &cholmod.common);
  cholmod_factor* factor = cholmod_analyze(matrix, &cholmod.common);
  if (factor == nullptr) Fail("cholmod_analyze failed");
  cholmod_factorize(matrix, factor, &cholmod.common);
  double log_det = -std::numeric_limits<double>::infinity();
  if (cholmod.common.status == CHOLMOD_OK && factor->minor == factor->n) {
    log_det = LogDetOfFactor(factor);
  } else if (cholmod.common.status != CHOLMOD_NOT_POSDEF) {
    Fail("cholmod_factorize failed");
  }
  cholmod_free_factor(&factor, &cholmod.common);
  cholmod_free_sparse(&matrix, &cholmod.common);
  return log_det;
}

double U1FromLogDet(double log_det, int num_nodes) {
  if (num_nodes < 1) Fail("U1 of a graph without vertices");
  // n^(1/n)·exp(log det/n) in log space: det itself overflows for large graphs.
  return std::exp((std::log(static_cast<double>(num_nodes)) + log_det) / num_nodes);
}

// The incremental way (docs/architecture.md §5). With A the base reduced Laplacian and the
// extended one [[A + ΔA, B], [Bᵀ, C]] (ΔA and B nonzero only on the few old
// nodes T that extension edges touch):
//   log det = log det A + log det(I + Rᵀ W R) + log det(C − B_Tᵀ S' B_T),
// where S = (A⁻¹)_TT = R Rᵀ, W = ΔA_TT (matrix determinant lemma in the
// symmetric form), S' = ((A + ΔA)⁻¹)_TT = R (I + Rᵀ W R)⁻¹ Rᵀ (Woodbury).
// With P A Pᵀ = L D Lᵀ, S_ij = y_iᵀ D⁻¹ y_j, y_i = L⁻¹ P e_i: one sparse
// forward solve per old node, cached for the life of this object.
struct IncrementalLogDet::Impl {
  struct SparseVector {
    std::vector<int> index;  // permuted positions (the etree path of the node)
    std::vector<double> value;
  };

  int num_base_nodes = 0;
  int n = 0;  // size of A = num_base_nodes - 1
  double base_log_det = 0.0;
  Cholmod cholmod;
  cholmod_factor* factor = nullptr;
  std::vector<int> inverse_perm;                 // node k-1 -> permuted position
  std::vector<double> inverse_d;                 // 1 / D, in permuted order
  std::unordered_map<int, SparseVector> solves;  // by reduced index k-1
  std::vector<int>
      etree_parent;          // parent of each permuted column in L's elimination tree; -1 at a root
  std::vector<double> work;  // all-zero between solves, size n

  ~Impl() {
    if (factor != nullptr) cholmod_free_factor(&factor, &cholmod.common);
  }

  // y = L⁻¹ e (unit L, permuted order) for e the unit vector of one node: nonzero
  // only on that node's elimination-tree path to the root, and every row of a
  // path column is on the path, so the solve walks the path column by column
  // (children first) — the column-oriented forward solve CHOLMOD's
  // cholmod_solve2(CHOLMOD_L) with a Bset runs, the same operations in the same
  // order, without its per-call pattern computation.
  const SparseVector& Solve(int reduced_index) {
    auto found = solves.find(reduced_index);
    if (found != solves.end()) return found->second;
    const auto* lp = static_cast<const int*>(factor->p);
    const auto* li = static_cast<const int*>(factor->i);
    const auto* lx = static_cast<const double*>(factor->x);
    const auto* lnz = static_cast<const int*>(factor->nz);
    SparseVector vector;
    const int position = inverse_perm[reduced_index];
    work[position] = 1.0;
    for (int j = position; j >= 0; j = etree_parent[j]) {
      const double yj = work[j];
      for (int p = lp[j] + 1; p < lp[j] + lnz[j]; ++p) work[li[p]] -= lx[p] * yj;
      vector.index.push_back(j);
      vector.value.push_back(yj);
      work[j] = 0.0;  // back to all-zero for the next solve
    }
    return solves.emplace(reduced_index, std::move(vector)).first->second;
  }

  // S = (A⁻¹)_TT, S_ij = y_iᵀ D⁻¹ y_j: scatter D⁻¹ y_i into a dense buffer, gather y_j.
  // Both vectors live on root paths of the elimination tree (ascending), so they
  // share exactly the path from their common ancestor to the root: a suffix of y_j,
  // found by binary search on a mark of y_i's path. Outside it the scatter is 0 and
  // each skipped term is ±0, which leaves the sum's bits alone. Four gathers run
  // interleaved, each in its own term order (same bits as one at a time), so four
  // independent add chains hide the add latency that bounds one.
  Eigen::MatrixXd InverseBlock(const std::vector<const SparseVector*>& y) {
    const int t = static_cast<int>(y.size());
    Eigen::MatrixXd block(t, t);
    const double* scattered = scatter.data();
    auto shared_from = [this](const SparseVector& b) {  // first entry of b on the marked path
      const auto first = std::partition_point(b.index.begin(), b.index.end(),
                                              [this](int k) { return mark[k] != stamp; });
      return static_cast<std::size_t>(first - b.index.begin());
    };
    auto dot_tail = [scattered](const SparseVector& b, std::size_t from, double sum) {
      for (std::size_t k = from; k < b.index.size(); ++k) sum += scattered[b.index[k]] * b.value[k];
      return sum;
    };
    for (int i = 0; i < t; ++i) {
      const SparseVector& a = *y[i];
      ++stamp;
      for (std::size_t k = 0; k < a.index.size(); ++k) {
        scatter[a.index[k]] = a.value[k] * inverse_d[a.index[k]];
        mark[a.index[k]] = stamp;
      }
      int j = 0;
      for (; j + 3 <= i; j += 4) {
        const SparseVector* b[4] = {y[j], y[j + 1], y[j + 2], y[j + 3]};
        std::size_t from[4];
        std::size_t common = std::numeric_limits<std::size_t>::max();
        for (int q = 0; q < 4; ++q) {
          from[q] = shared_from(*b[q]);
          common = std::min(common, b[q]->index.size() - from[q]);
        }
        double sum[4] = {0.0, 0.0, 0.0, 0.0};
        for (std::size_t k = 0; k < common; ++k) {
          for (int q = 0; q < 4; ++q) {
            sum[q] += scattered[b[q]->index[from[q] + k]] * b[q]->value[from[q] + k];
          }
        }
        for (int q = 0; q < 4; ++q) {
          const double value = dot_tail(*b[q], from[q] + common, sum[q]);
          block(i, j + q) = block(j + q, i) = value;
        }
      }
      for (; j <= i; ++j) block(i, j) = block(j, i) = dot_tail(*y[j], shared_from(*y[j]), 0.0);
      for (int k : a.index) scatter[k] = 0.0;  // back to all-zero for the next row
    }
    return block;
  }

  std::vector<unsigned> mark;  // mark[k] == stamp: k is on the path InverseBlock scattered
  unsigned stamp = 0;
  std::vector<double> scatter;  // all-zero between uses, size n
};

IncrementalLogDet::IncrementalLogDet(const WeightedGraph& base) : impl_(std::make_unique<Impl>()) {
  Impl& m = *impl_;
  if (base.num_nodes < 1) Fail("IncrementalLogDet of an empty graph");
  m.num_base_nodes = base.num_nodes;
  m.n = base.num_nodes - 1;
  if (m.n == 0) return;  // A is empty: every extension is its own block C
  cholmod_common* c = &m.cholmod.common;
  cholmod_sparse* matrix = BuildReducedLaplacian(base, {}, c);
  m.factor = cholmod_analyze(matrix, c);
  if (m.factor == nullptr) Fail("cholmod_analyze failed");
  cholmod_factorize(matrix, m.factor, c);
  cholmod_free_sparse(&matrix, c);
  if (c->status != CHOLMOD_OK || m.factor->minor != m.factor->n) {
    Fail("base graph not connected: its reduced Laplacian is not positive definite");
  }
  if (m.factor->is_super || m.factor->is_ll) Fail("expected a simplicial LDLᵀ factor");
  m.base_log_det = LogDetOfFactor(m.factor);
  const auto* perm = static_cast<const int*>(m.factor->Perm);
  const auto* p = static_cast<const int*>(m.factor->p);
  const auto* x = static_cast<const double*>(m.factor->x);
  m.inverse_perm.resize(m.n);
  m.inverse_d.resize(m.n);
  m.scatter.assign(m.n, 0.0);
  m.mark.assign(m.n, 0);
  for (int k = 0; k < m.n; ++k) {
    m.inverse_perm[perm[k]] = k;
    m.inverse_d[k] = 1.0 / x[p[k]];  // D sits on L's diagonal in a simplicial LDLᵀ
  }
  // The etree parent of column j is its smallest off-diagonal row (its first, in a sorted factor).
  const auto* li = static_cast<const int*>(m.factor->i);
  const auto* lnz = static_cast<const int*>(m.factor->nz);
  m.etree_parent.assign(m.n, -1);
  for (int j = 0; j < m.n; ++j) {
    for (int q = p[j] + 1; q < p[j] + lnz[j]; ++q) {
      if (li[q] <= j) Fail("unexpected entry above the diagonal of L");
      if (m.etree_parent[j] < 0 || li[q] < m.etree_parent[j]) m.etree_parent[j] = li[q];
    }
  }
  m.work.assign(m.n, 0.0);
}

IncrementalLogDet::~IncrementalLogDet() = default;

double IncrementalLogDet::base_log_det() const { return impl_->base_log_det; }

int IncrementalLogDet::cached_solves() const { return static_cast<int>(impl_->solves.size()); }

double IncrementalLogDet::LogDet(const GraphExtension& extension) {
  Impl& m = *impl_;
  const int num_base = m.num_base_nodes;
  const int num_new = extension.num_new_nodes;
  if (num_new < 0) Fail("negative number of new nodes");
  const int num_nodes = num_base + num_new;

  // T: old non-root nodes touched by extension edges, in first-seen order.
  std::vector<int> touched;  // reduced indices (node - 1)
  std::unordered_map<int, int> slot;
  auto slot_of = [&](int node) {
    auto [it, inserted] = slot.emplace(node - 1, static_cast<int>(touched.size()));
    if (inserted) touched.push_back(node - 1);
    return it->second;
  };
  for (const WeightedEdge& edge : extension.edges) {
    CheckEdge(edge, num_nodes);
    if (edge.from == edge.to) continue;
    if (edge.from >= 1 && edge.from < num_base) slot_of(edge.from);
    if (edge.to >= 1 && edge.to < num_base) slot_of(edge.to);
  }
  const int t = static_cast<int>(touched.size());

  // W = ΔA_TT, B_T (T × new) and C (new × new; new node num_base + k -> k).
  Eigen::MatrixXd w = Eigen::MatrixXd::Zero(t, t);
  Eigen::MatrixXd b = Eigen::MatrixXd::Zero(t, num_new);
  Eigen::MatrixXd c = Eigen::MatrixXd::Zero(num_new, num_new);
  auto is_old = [&](int node) { return node >= 1 && node < num_base; };
  auto is_new = [&](int node) { return node >= num_base; };
  for (const WeightedEdge& edge : extension.edges) {
    if (edge.from == edge.to) continue;
    const double weight = edge.weight;
    for (int end = 0; end < 2; ++end) {  // each end's diagonal
      const int node = end == 0 ? edge.from : edge.to;
      if (is_old(node)) {
        const int s = slot.at(node - 1);
        w(s, s) += weight;
      } else if (is_new(node)) {
        c(node - num_base, node - num_base) += weight;
      }  // node 0: not in the reduced system
    }
    const int u = edge.from, v = edge.to;
    if (is_old(u) && is_old(v)) {
      const int su = slot.at(u - 1), sv = slot.at(v - 1);
      w(su, sv) -= weight;
      w(sv, su) -= weight;
    } else if (is_new(u) && is_new(v)) {
      c(u - num_base, v - num_base) -= weight;
      c(v - num_base, u - num_base) -= weight;
    } else if (is_old(u) && is_new(v)) {
      b(slot.at(u - 1), v - num_base) -= weight;
    } else if (is_new(u) && is_old(v)) {
      b(slot.at(v - 1), u - num_base) -= weight;
    }
  }

  double log_det = m.base_log_det;
  if (t > 0) {
    // S = (A⁻¹)_TT from the cached forward solves.
    std::vector<const Impl::SparseVector*> y(t);
    for (int s = 0; s < t; ++s) y[s] = &m.Solve(touched[s]);
    const Eigen::MatrixXd s_matrix = m.InverseBlock(y);
    const Eigen::LLT<Eigen::MatrixXd> s_llt(s_matrix);
    if (s_llt.info() != Eigen::Success) Fail("(A⁻¹)_TT not positive definite");
    const Eigen::MatrixXd r = s_llt.matrixL();
    const Eigen::MatrixXd q = Eigen::MatrixXd::Identity(t, t) + r.transpose() * w * r;
    const Eigen::LLT<Eigen::MatrixXd> q_llt(q);
    if (q_llt.info() != Eigen::Success) Fail("I + RᵀWR not positive definite");
    log_det += 2.0 * q_llt.matrixLLT().diagonal().array().log().sum();
    if (num_new > 0) {
      // C − B_Tᵀ S' B_T with S' = R Q⁻¹ Rᵀ: form Rᵀ B_T once.
      const Eigen::MatrixXd rt_b = r.transpose() * b;
      c -= rt_b.transpose() * q_llt.solve(rt_b);
    }
  }
  if (num_new > 0) {
    const Eigen::LLT<Eigen::MatrixXd> c_llt(c);
    // A new node without a path to the base graph: no spanning tree.
    if (c_llt.info() != Eigen::Success) return -std::numeric_limits<double>::infinity();
    log_det += 2.0 * c_llt.matrixLLT().diagonal().array().log().sum();
  }
  return log_det;
}

}  // namespace aslam
