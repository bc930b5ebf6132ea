#include "nso_level.h"

#include <omp.h>

#include <algorithm>
#include <cmath>

namespace pliant::smoke {

NsoLevel::NsoLevel(const SpacetimeGrid& sg) : sg_(sg) {
  const size_t TF = size_t(sg.T) * sg.faces(), TC = size_t(sg.T) * sg.cells();
  x.assign(TF, 0.0);
  F.assign(TF, 0.0);
  res_mom.assign(TF, 0.0);
  zbar.assign(TF, 0.0);
  q.assign(TC, 0.0);
  G.assign(TC, 0.0);
  res_div.assign(TC, 0.0);
  wall_.resize(sg.faces());
  for (size_t f = 0; f < sg.faces(); ++f) wall_[f] = is_wall_face(sg, f);
  for (int a = 0; a < 3; ++a) lay_[a] = sg.g.face_layout(a);
  A_.resize(std::max(0, sg.T - 1));
  ata_diag_.assign(size_t(std::max(0, sg.T - 1)) * sg.faces(), 0.0f);
  ata_hi_.assign(ata_diag_.size(), 0.0f);
  frame_sm_.assign(sg.T, 0.0);
  frame_sd_.assign(sg.T, 0.0);
  ensure_scratch();
}

void NsoLevel::ensure_scratch() {
  // Per-thread block scratch; re-checked before each sweep because callers may raise
  // the thread count after construction (SerialBelow scopes).
  const size_t threads = size_t(std::max(1, omp_get_max_threads()));
  if (scratch_.size() >= threads) return;
  const int m = 2 * sg_.g.dim + 1;
  const size_t blocks = size_t(sg_.T) * m * m;
  scratch_.resize(threads);
  for (auto& s : scratch_) {
    if (!s.B.empty()) continue;
    s.B.resize(blocks), s.L.resize(blocks), s.U.resize(blocks), s.schur.resize(blocks), s.sinv_u.resize(blocks);
    s.rhs.resize(size_t(sg_.T) * m);
    s.piv.resize(size_t(sg_.T) * m);
    s.e0.resize(sg_.faces());
    s.e1.resize(sg_.faces());
  }
}

size_t NsoLevel::bytes() const {
  size_t b = (x.capacity() + q.capacity() + F.capacity() + G.capacity() + res_mom.capacity() +
              res_div.capacity() + zbar.capacity()) * sizeof(double) +
             (ata_diag_.capacity() + ata_hi_.capacity()) * sizeof(float) + wall_.capacity();
  for (const SlStencil& a : A_) b += a.rows.capacity() * sizeof(SlRow);
  for (const ThreadScratch& s : scratch_)
    b += (s.B.capacity() + s.L.capacity() + s.U.capacity() + s.rhs.capacity() + s.schur.capacity() +
          s.sinv_u.capacity() + s.e0.capacity() + s.e1.capacity()) * sizeof(double) + s.piv.capacity() * sizeof(int);
  return b;
}

void NsoLevel::linearise(const double* zb, double dt) {
  const size_t Fn = sg_.faces();
  if (zb != zbar.data()) std::copy(zb, zb + size_t(sg_.T) * Fn, zbar.begin());
  ensure_scratch();
#pragma omp parallel for schedule(dynamic) if (sg_.parallel())
  for (int t = 0; t < sg_.T - 1; ++t) {
    ThreadScratch& s = scratch_[omp_get_thread_num()];
    build_sl_stencil(sg_, zbar.data() + t * Fn, dt, A_[t]);
    sl_ata(sg_, A_[t], s.e0.data(), s.e1.data());
    float* dg = ata_diag_.data() + t * Fn;
    float* hg = ata_hi_.data() + t * Fn;
    for (size_t f = 0; f < Fn; ++f) dg[f] = float(s.e0[f]), hg[f] = float(s.e1[f]);
  }
}

void NsoLevel::frame_defect(const double* xx, int t, double* e) const {
  const size_t Fn = sg_.faces();
  const double* xt = xx + t * Fn;
  if (t == 0) {
    std::copy(xt, xt + Fn, e);
    return;
  }
  sl_apply(sg_, A_[t - 1], xx + (t - 1) * Fn, e);
  for (size_t f = 0; f < Fn; ++f) e[f] = xt[f] - e[f];
}

void NsoLevel::apply_frames(const double* xx, const double* qq, double* out_mom, double* out_div,
                            const double* Fr, const double* Gr) {
  const MacGrid& g = sg_.g;
  const size_t Fn = sg_.faces(), Cn = sg_.cells();
  const int T = sg_.T;
  const double inv_h = 1.0 / g.h;
  // A contiguous run of frames walked backwards, so the defect e_{t+1} = x_{t+1} - A_t x_t
  // of the previous step is reused (no T*faces scratch; one extra defect per run).
  const int nth = omp_get_num_threads(), tid = omp_get_thread_num();
  const int t0 = int(int64_t(T) * tid / nth), t1 = int(int64_t(T) * (tid + 1) / nth);
  ThreadScratch& s = scratch_[tid];
  double *cur = s.e0.data(), *next = s.e1.data();
  if (t1 > t0 && t1 < T) frame_defect(xx, t1, next);
  for (int t = t1 - 1; t >= t0; --t) {
    frame_defect(xx, t, cur);
    double* o = out_mom + t * Fn;
    const double* xt = xx + t * Fn;
    for (size_t f = 0; f < Fn; ++f) o[f] = w_ * cur[f] + bm_ * xt[f];
    if (t + 1 < T) sl_apply_transpose_add(sg_, A_[t], -w_, next, o);
    std::swap(cur, next);
    // D^T q and D x, cell by cell.
    const double* qt = qq + t * Cn;
    double* d = out_div + t * Cn;
    for (int k = 0; k < g.n[2]; ++k)
      for (int j = 0; j < g.n[1]; ++j)
        for (int i = 0; i < g.n[0]; ++i) {
          const size_t c = g.cell(i, j, k);
          double div = 0;
          for (int a = 0; a < g.dim; ++a) {
            const size_t lo = sg_.off[a] + g.face_lo(a, i, j, k), hi = sg_.off[a] + g.face_hi(a, i, j, k);
            div += xt[hi] - xt[lo];
            o[hi] += inv_h * qt[c];
            o[lo] -= inv_h * qt[c];
          }
          d[c] = inv_h * div;
        }
    if (!Fr) {
      for (size_t f = 0; f < Fn; ++f)
        if (wall_[f]) o[f] = xt[f];
      continue;
    }
    double sm = 0, sd = 0;
    const double* Ft = Fr + t * Fn;
    for (size_t f = 0; f < Fn; ++f) {
      o[f] = wall_[f] ? 0.0 : Ft[f] - o[f];  // walls are fixed, not solved
      sm += o[f] * o[f];
    }
    const double* Gt = Gr + t * Cn;
    for (size_t c = 0; c < Cn; ++c) {
      d[c] = Gt[c] - d[c];
      sd += d[c] * d[c];
    }
    frame_sm_[t] = sm, frame_sd_[t] = sd;
  }
}

void NsoLevel::apply(const double* xx, const double* qq, double* out_mom, double* out_div) {
  ensure_scratch();
#pragma omp parallel if (sg_.parallel())
  apply_frames(xx, qq, out_mom, out_div, nullptr, nullptr);
}

double NsoLevel::residual() {
  ensure_scratch();
#pragma omp parallel if (sg_.parallel())
  apply_frames(x.data(), q.data(), res_mom.data(), res_div.data(), F.data(), G.data());
  double sm = 0, sd = 0;
  for (int t = 0; t < sg_.T; ++t) sm += frame_sm_[t], sd += frame_sd_[t];
  const double s = w_ * sg_.g.h;
  return std::sqrt(sm + s * s * sd);
}

void NsoLevel::solve_cell(int i, int j, int k, int thread) {
  const MacGrid& g = sg_.g;
  const int dim = g.dim, m = 2 * dim + 1, mm = m * m, T = sg_.T;
  const size_t Fn = sg_.faces(), Cn = sg_.cells();
  const size_t c = g.cell(i, j, k);
  size_t phi[6];
  bool wall[6];
  double sgn[6];
  for (int a = 0; a < dim; ++a) {
    phi[2 * a] = sg_.off[a] + g.face_lo(a, i, j, k);
    phi[2 * a + 1] = sg_.off[a] + g.face_hi(a, i, j, k);
    sgn[2 * a] = -1.0 / g.h;
    sgn[2 * a + 1] = 1.0 / g.h;
  }
  for (int p = 0; p < 2 * dim; ++p) wall[p] = wall_[phi[p]];
  // Coordinates of the cell's faces in their component's layout (hi: +1, wrapped).
  int coord[6][3];
  for (int a = 0; a < dim; ++a) {
    int* lo = coord[2 * a];
    int* hi = coord[2 * a + 1];
    lo[0] = hi[0] = i, lo[1] = hi[1] = j, lo[2] = hi[2] = k;
    hi[a] = g.periodic && hi[a] + 1 == g.n[a] ? 0 : hi[a] + 1;
  }
  ThreadScratch& s = scratch_[thread];
  // Only the structurally non-zero entries are written (walls write zeros there), so
  // B, L, U keep their zero pattern from the allocation: no fills per cell.
  const int qi = 2 * dim;
  for (int t = 0; t < T; ++t) {
    double* B = s.B.data() + size_t(t) * mm;
    double* r = s.rhs.data() + size_t(t) * m;
    const bool coupled = t + 1 < T;
    const float* ad = coupled ? ata_diag_.data() + t * Fn : nullptr;
    const float* ah = coupled ? ata_hi_.data() + t * Fn : nullptr;
    for (int p = 0; p < 2 * dim; ++p) {
      if (wall[p]) {
        B[p * m + p] = 1.0;
        B[p * m + qi] = B[qi * m + p] = 0.0;
        r[p] = 0.0;
        continue;
      }
      B[p * m + p] = w_ + bm_ + (coupled ? w_ * ad[phi[p]] : 0.0);
      B[p * m + qi] = B[qi * m + p] = sgn[p];
      r[p] = res_mom[t * Fn + phi[p]];
    }
    r[qi] = res_div[t * Cn + c];
    for (int a = 0; a < dim; ++a) {
      const int lo = 2 * a, hi = 2 * a + 1;
      const double v = wall[lo] || wall[hi] || !coupled ? 0.0 : w_ * ah[phi[lo]];
      B[lo * m + hi] = v;
      B[hi * m + lo] = v;
    }
    if (t > 0) {  // L_t = -w A_{t-1}[local, local]; U_{t-1} = L_t^T
      double* L = s.L.data() + size_t(t) * mm;
      double* U = s.U.data() + size_t(t - 1) * mm;
      const SlRow* rows = A_[t - 1].rows.data();
      for (int a = 0; a < dim; ++a) {
        const FieldLayout& l = lay_[a];
        for (int p = 2 * a; p < 2 * a + 2; ++p)
          for (int pp = 2 * a; pp < 2 * a + 2; ++pp) {
            const double v =
                wall[p] || wall[pp] ? 0.0 : -w_ * sl_entry_at(l, dim, rows[phi[p]], coord[pp]);
            L[p * m + pp] = v;
            U[pp * m + p] = v;
          }
      }
    }
  }
  const BlockTridiagonalScratch bs{s.schur.data(), s.sinv_u.data(), s.piv.data()};
  if (!block_tridiagonal_solve(T, m, s.B.data(), s.L.data(), s.U.data(), s.rhs.data(), bs)) return;
  for (int t = 0; t < T; ++t) {
    const double* d = s.rhs.data() + size_t(t) * m;
    for (int p = 0; p < 2 * dim; ++p)
      if (!wall[p]) x[t * Fn + phi[p]] += d[p];
    q[t * Cn + c] += d[qi];
  }
}

void NsoLevel::smooth(bool forward) {
  ensure_scratch();
  const MacGrid& g = sg_.g;
  const int colours = 1 << g.dim;
#pragma omp parallel if (sg_.parallel())
  for (int n = 0; n < colours; ++n) {
    const int colour = forward ? n : colours - 1 - n;
    apply_frames(x.data(), q.data(), res_mom.data(), res_div.data(), F.data(), G.data());
#pragma omp barrier
    const int pi = colour & 1, pj = (colour >> 1) & 1, pk = (colour >> 2) & 1;
    const int nj = (g.n[1] - pj + 1) / 2, nk = g.dim == 3 ? (g.n[2] - pk + 1) / 2 : 1;
    const int thread = omp_get_thread_num();
#pragma omp for collapse(2) schedule(dynamic, 4)
    for (int kk = 0; kk < nk; ++kk)
      for (int jj = 0; jj < nj; ++jj) {
        const int k = g.dim == 3 ? 2 * kk + pk : 0, j = 2 * jj + pj;
        for (int i = pi; i < g.n[0]; i += 2) solve_cell(i, j, k, thread);
      }
  }
}

}  // namespace pliant::smoke
