// Tet-mesh quality (Yan, Wang, Levy, Liu, CAD 2011, sec. 6): the per-tet measures Q1..Q4,
// their statistics and histograms over a mesh, and the exact orientation census that
// tells inverted and degenerate tets apart.
//
// Determinism: tets are cut into blocks of kBlock (a constant, not a function of the
// thread count); each block is reduced sequentially into its own slot, and the slots are
// combined in block order. Sums, minima (lowest tet on ties) and histograms are therefore
// the same bits for any number of threads.
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <string>
#include <vector>

#include "voroclip/mesh.h"
#include "voroclip/predicates.h"

namespace voroclip {

namespace {

constexpr std::uint32_t kBlock = 2048;
constexpr double kRadToDeg = 180.0 / 3.14159265358979323846;

inline void cross(const double* a, const double* b, double* out) {
  out[0] = a[1] * b[2] - a[2] * b[1];
  out[1] = a[2] * b[0] - a[0] * b[2];
  out[2] = a[0] * b[1] - a[1] * b[0];
}
inline double dot(const double* a, const double* b) {
  return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}
inline double norm(const double* a) { return std::sqrt(dot(a, a)); }

// Bin of v among `bins` bins over [lo, hi], the last one closed.
inline std::size_t bin_of(double v, double lo, double hi, std::uint32_t bins) {
  const double x = (v - lo) / (hi - lo) * bins;
  if (!(x > 0)) return 0;
  return std::min<std::size_t>(static_cast<std::size_t>(x), bins - 1);
}

// A running min / sum / max with the lowest index reaching each extreme.
struct Accumulator {
  double min = std::numeric_limits<double>::infinity();
  double max = -std::numeric_limits<double>::infinity();
  double sum = 0;
  std::uint64_t count = 0;
  std::uint32_t argmin = 0, argmax = 0;

  void add(double v, std::uint32_t at) {
    if (v < min) {
      min = v;
      argmin = at;
    }
    if (v > max) {
      max = v;
      argmax = at;
    }
    sum += v;
    ++count;
  }
  // `o` covers later tets than *this: on equal extremes the earlier tet stays.
  void merge(const Accumulator& o) {
    if (o.min < min) {
      min = o.min;
      argmin = o.argmin;
    }
    if (o.max > max) {
      max = o.max;
      argmax = o.argmax;
    }
    sum += o.sum;
    count += o.count;
  }
  QualityStat stat() const {
    QualityStat s;
    if (count == 0) return s;
    s.min = min;
    s.max = max;
    s.mean = sum / static_cast<double>(count);
    s.argmin = argmin;
    s.argmax = argmax;
    return s;
  }
};

struct BlockResult {
  Accumulator q1, q2, q3, q4, dihedral;
  std::vector<std::uint64_t> dihedral_hist, min_dihedral_hist, q3_hist, q4_hist;
  std::uint32_t positive = 0, negative = 0;
};

}  // namespace

std::vector<VtuCellField> tet_quality_fields(const TetMeshInput& mesh) {
  std::vector<VtuCellField> fields(1);
  fields[0].name = "q1_min_dihedral_deg";
  const std::size_t nt = mesh.tets.size() / 4, nf = mesh.triangles.size() / 3;
  fields[0].values.reserve(nt + nf);
  for (std::size_t t = 0; t < nt; ++t) {
    const std::uint32_t* v = &mesh.tets[4 * t];
    fields[0].values.push_back(
        tet_shape(&mesh.xyz[3 * std::size_t{v[0]}], &mesh.xyz[3 * std::size_t{v[1]}],
                  &mesh.xyz[3 * std::size_t{v[2]}], &mesh.xyz[3 * std::size_t{v[3]}])
            .q1_deg);
  }
  fields[0].values.resize(nt + nf, std::numeric_limits<double>::quiet_NaN());
  return fields;
}

TetShape tet_shape(const double* p0, const double* p1, const double* p2, const double* p3) {
  TetShape shape;
  const Sign o = orient3d(p0, p1, p2, p3);
  if (o == Sign::zero) return shape;
  shape.degenerate = false;
  shape.positive = o == Sign::negative;  // orient3d = -sign det(p1 - p0, p2 - p0, p3 - p0)
  const double* p[4] = {p0, p1, p2, p3};
  // Edge vectors e[k] = p[j] - p[i] for kTetEdges[k] = (i, j), scaled by a power of two
  // that brings the largest component into [1, 2).
  double e[6][3];
  double largest = 0;
  for (int k = 0; k < 6; ++k) {
    for (int c = 0; c < 3; ++c) {
      e[k][c] = p[TetShape::kTetEdges[k][1]][c] - p[TetShape::kTetEdges[k][0]][c];
      largest = std::max(largest, std::fabs(e[k][c]));
    }
  }
  // The scaling is exact. A multiplication by 2^-exponent (a power of two a double holds
  // when exponent >= -1022) rounds as ldexp does, without its 18 library calls: they were
  // 15 % of step 7c's time on skull_low_resolution at 1,000 vertices (session 30).
  const int exponent = std::ilogb(largest);
  if (exponent >= -1022) {
    const double scale = std::ldexp(1.0, -exponent);
    for (auto& v : e) {
      for (double& x : v) x *= scale;
    }
  } else {
    for (auto& v : e) {
      for (double& x : v) x = std::ldexp(x, -exponent);
    }
  }
  const double* e01 = e[0];
  const double* e02 = e[1];
  const double* e03 = e[2];
  const double* e12 = e[3];
  const double* e13 = e[4];
  // Face normals, face k opposite vertex k, outward when det > 0 (all inward otherwise;
  // the dihedral angles do not depend on which).
  double n[4][3];
  cross(e12, e13, n[0]);
  cross(e03, e02, n[1]);
  cross(e01, e03, n[2]);
  cross(e02, e01, n[3]);
  // Edge (i, j) lies on the faces opposite the two other vertices.
  static constexpr int kOpposite[6][2] = {{2, 3}, {1, 3}, {1, 2}, {0, 3}, {0, 2}, {0, 1}};
  shape.q1_deg = 180;
  shape.q2_deg = 0;
  for (int k = 0; k < 6; ++k) {
    const double* a = n[kOpposite[k][0]];
    const double* b = n[kOpposite[k][1]];
    double x[3];
    cross(a, b, x);
    const double angle = std::atan2(norm(x), -dot(a, b)) * kRadToDeg;
    shape.dihedral_deg[k] = angle;
    shape.q1_deg = std::min(shape.q1_deg, angle);
    shape.q2_deg = std::max(shape.q2_deg, angle);
  }
  double bc[3], ca[3], ab[3];
  cross(e02, e03, bc);
  cross(e03, e01, ca);
  cross(e01, e02, ab);
  const double det = dot(e01, bc);
  const double la = dot(e01, e01), lb = dot(e02, e02), lc = dot(e03, e03);
  double sum_l2 = 0;
  for (const auto& v : e) sum_l2 += dot(v, v);
  double num[3];
  for (int c = 0; c < 3; ++c) num[c] = la * bc[c] + lb * ca[c] + lc * ab[c];
  const double area = 0.5 * (norm(n[0]) + norm(n[1]) + norm(n[2]) + norm(n[3]));
  const double denominator = area * norm(num);
  shape.q3 = denominator > 0 ? 3 * det * det / denominator : 0.0;
  shape.q4 = sum_l2 > 0 ? 12 * std::cbrt(det * det / 4) / sum_l2 : 0.0;
  shape.volume = std::ldexp(det, 3 * exponent) / 6;
  return shape;
}

TetQuality tet_quality(const double* xyz, std::uint32_t nb_vertices, const std::uint32_t* tets,
                       std::uint32_t nb_tets, const TetQualityOptions& options) {
  if (options.dihedral_bins == 0 || options.quality_bins == 0) {
    throw Error("tet_quality: the histograms need at least one bin");
  }
  TetQuality q;
  q.nb_tets = nb_tets;
  q.nb_vertices = nb_vertices;
  std::vector<std::uint8_t> used(nb_vertices, 0);
  for (std::uint32_t t = 0; t < nb_tets; ++t) {
    for (std::size_t k = 0; k < 4; ++k) {
      const std::uint32_t v = tets[4 * std::size_t{t} + k];
      if (v >= nb_vertices) {
        throw Error("tet " + std::to_string(t) + " has vertex " + std::to_string(v) +
                    ", the mesh has " + std::to_string(nb_vertices) +
                    " vertices (numbered from 0)");
      }
      if (!used[v]) {
        const double* p = xyz + 3 * std::size_t{v};
        if (!std::isfinite(p[0]) || !std::isfinite(p[1]) || !std::isfinite(p[2])) {
          throw Error("tet " + std::to_string(t) + ": vertex " + std::to_string(v) +
                      " has a non-finite coordinate (numbered from 0)");
        }
        used[v] = 1;
        ++q.nb_used_vertices;
      }
    }
  }
  const std::uint32_t db = options.dihedral_bins, qb = options.quality_bins;
  q.dihedral_histogram.assign(db, 0);
  q.min_dihedral_histogram.assign(db, 0);
  q.q3_histogram.assign(qb, 0);
  q.q4_histogram.assign(qb, 0);
  if (options.keep_per_tet) q.per_tet.resize(nb_tets);
  // Orientation per tet: +1 positive, -1 negative, 0 degenerate.
  std::vector<std::int8_t> sign(nb_tets, 0);
  const std::uint32_t nb_blocks = (nb_tets + kBlock - 1) / kBlock;
  std::vector<BlockResult> blocks(nb_blocks);
  tbb::parallel_for(tbb::blocked_range<std::uint32_t>(0, nb_blocks), [&](const auto& range) {
    for (std::uint32_t b = range.begin(); b != range.end(); ++b) {
      BlockResult& r = blocks[b];
      r.dihedral_hist.assign(db, 0);
      r.min_dihedral_hist.assign(db, 0);
      r.q3_hist.assign(qb, 0);
      r.q4_hist.assign(qb, 0);
      const std::uint32_t end = std::min(nb_tets, (b + 1) * kBlock);
      for (std::uint32_t t = b * kBlock; t < end; ++t) {
        const std::uint32_t* v = tets + 4 * std::size_t{t};
        const TetShape s = tet_shape(xyz + 3 * std::size_t{v[0]}, xyz + 3 * std::size_t{v[1]},
                                     xyz + 3 * std::size_t{v[2]}, xyz + 3 * std::size_t{v[3]});
        if (options.keep_per_tet) q.per_tet[t] = s;
        r.q1.add(s.q1_deg, t);
        r.q2.add(s.q2_deg, t);
        r.q3.add(s.q3, t);
        r.q4.add(s.q4, t);
        ++r.min_dihedral_hist[bin_of(s.q1_deg, 0, 180, db)];
        ++r.q3_hist[bin_of(s.q3, 0, 1, qb)];
        ++r.q4_hist[bin_of(s.q4, 0, 1, qb)];
        if (s.degenerate) continue;
        sign[t] = s.positive ? 1 : -1;
        ++(s.positive ? r.positive : r.negative);
        for (const double angle : s.dihedral_deg) {
          r.dihedral.add(angle, t);
          ++r.dihedral_hist[bin_of(angle, 0, 180, db)];
        }
      }
    }
  });
  BlockResult total;
  for (const BlockResult& r : blocks) {
    total.q1.merge(r.q1);
    total.q2.merge(r.q2);
    total.q3.merge(r.q3);
    total.q4.merge(r.q4);
    total.dihedral.merge(r.dihedral);
    for (std::uint32_t i = 0; i < db; ++i) {
      q.dihedral_histogram[i] += r.dihedral_hist[i];
      q.min_dihedral_histogram[i] += r.min_dihedral_hist[i];
    }
    for (std::uint32_t i = 0; i < qb; ++i) {
      q.q3_histogram[i] += r.q3_hist[i];
      q.q4_histogram[i] += r.q4_hist[i];
    }
    q.nb_positive += r.positive;
    q.nb_negative += r.negative;
  }
  q.q1_deg = total.q1.stat();
  q.q2_deg = total.q2.stat();
  q.q3 = total.q3.stat();
  q.q4 = total.q4.stat();
  q.dihedral_deg = total.dihedral.stat();
  // The majority orientation; on a tie, that of the first non-degenerate tet.
  std::int8_t majority = q.nb_positive > q.nb_negative ? 1 : -1;
  if (q.nb_positive == q.nb_negative) {
    for (const std::int8_t s : sign) {
      if (s != 0) {
        majority = s;
        break;
      }
    }
  }
  for (std::uint32_t t = 0; t < nb_tets; ++t) {
    if (sign[t] == 0) {
      q.degenerate.push_back(t);
    } else if (sign[t] != majority) {
      q.inverted.push_back(t);
    }
  }
  return q;
}

TetQuality tet_quality(const TetMeshInput& mesh, const TetQualityOptions& options) {
  if (mesh.xyz.size() % 3 != 0 || mesh.tets.size() % 4 != 0) {
    throw Error(mesh.source + ": mesh arrays of " + std::to_string(mesh.xyz.size()) +
                " coordinates and " + std::to_string(mesh.tets.size()) + " tet indices");
  }
  try {
    return tet_quality(mesh.xyz.data(), mesh.nb_vertices(), mesh.tets.data(), mesh.nb_tets(),
                       options);
  } catch (const Error& e) {
    throw Error(mesh.source + ": " + e.what());
  }
}

}  // namespace voroclip
