// One level of the NSO spacetime problem, linearised (Picard) around zbar:
//   min_x  (w/2) sum_t ||x_t - A_{t-1} x_{t-1}||^2 + (bm/2) sum_t ||x_t||^2 - <F, x>
//   s.t.   D x_t = G_t                                  (t = 0..T-1 is frame t+1)
// with w = 2 r / dt^2 (so (w/2)||e||^2 = r ||e/dt||^2 = r ||f||^2), bm = beta + mu
// (ADMM penalty plus Levenberg-Marquardt damping), x_{-1} = 0 (rest at frame 0),
// D the MAC divergence (1/h scaled, so it rediscretises consistently on coarse
// levels) and A_t the frozen semi-Lagrangian operator (nso_advection_stencil.h).
// KKT system, unknowns x (all faces of all frames) and q (one dual per cell and
// frame):
//   H x + D^T q = F,   D x = G,
//   H = block-tridiagonal in time: diag w(I + A_t^T A_t) + bm I, off -w A_{t-1}.
// Closed-wall faces are fixed at 0 (their rows are identities).
// SCGS smoothing (Vanka type): for one cell, its 2*dim faces and its dual over all
// T frames form a block-tridiagonal system with (2*dim+1)^2 blocks equal to the
// corresponding principal submatrix of the KKT matrix (exact: A^T A couples a
// cell's two faces of one axis, which is included); it is solved by block Thomas
// (scgs_block_tridiagonal.h). Cells of one of the 2^dim parity colours share no
// face, so one colour is updated in parallel from a residual computed before it.
// Threads: one OpenMP region per sweep; per colour, each thread computes the residual of
// a contiguous run of frames, one barrier, then the colour's cells are shared out (a
// second barrier): 2 barriers per colour instead of 4 fork/joins (an oversubscribed
// machine makes every barrier cost a scheduler time slice). Norms are summed per frame
// and then over frames in order, so results do not depend on the thread count.
#pragma once
#include <vector>

#include "nso_advection_stencil.h"
#include "scgs_block_tridiagonal.h"

namespace pliant::smoke {

class NsoLevel {
 public:
  explicit NsoLevel(const SpacetimeGrid& sg);

  const SpacetimeGrid& grid() const { return sg_; }
  // Rebuild A_t from zbar (T*faces values; frame t's A uses zbar frame t).
  void linearise(const double* zbar, double dt);
  void set_coefficients(double w, double bm) { w_ = w, bm_ = bm; }
  double w() const { return w_; }
  double bm() const { return bm_; }

  // out = KKT operator applied to (x, q).
  void apply(const double* x, const double* q, double* out_mom, double* out_div);
  // res = (F, G) - KKT (x, q); returns the scaled norm sqrt(|r_mom|^2 + (w h)^2 |r_div|^2).
  double residual();
  // One SCGS sweep over the 2^dim colours (reversed order when !forward).
  void smooth(bool forward);

  // Unknowns, right-hand side and residual (T*faces / T*cells).
  std::vector<double> x, q, F, G, res_mom, res_div;
  std::vector<double> zbar;  // linearisation point (restricted on coarse levels)

  // Bytes held by this level (arrays and stencils), for memory reports.
  size_t bytes() const;

 private:
  // The calling thread's share (a contiguous run of frames, by omp_get_thread_num /
  // omp_get_num_threads) of out = KKT (xx, qq); with Fr/Gr, out is turned into the
  // residual (Fr, Gr) - out (walls 0) and its per-frame squared norms are stored.
  void apply_frames(const double* xx, const double* qq, double* out_mom, double* out_div, const double* Fr,
                    const double* Gr);
  void ensure_scratch();
  void solve_cell(int i, int j, int k, int thread);
  // A_{t-1} x_{t-1} subtracted from x_t (e_t of the header comment) into e (one frame).
  void frame_defect(const double* xx, int t, double* e) const;
  // A_t^T A_t entries SCGS needs, from the stencil of frame t (into ata_diag_/ata_hi_).
  void build_ata(int t, double* diag, double* hi);

  SpacetimeGrid sg_;
  double w_ = 1, bm_ = 1;
  std::vector<SlStencil> A_;       // T-1 operators (A_t: frame t -> t+1)
  // (A_t^T A_t)[phi, phi] and [phi, hi partner of phi] (face_hi_partner), (T-1)*faces,
  // float: they only shape the SCGS blocks (a smoother), never the residual.
  std::vector<float> ata_diag_, ata_hi_;
  std::vector<uint8_t> wall_;      // per face
  FieldLayout lay_[3];             // face layouts per component
  struct ThreadScratch {
    std::vector<double> B, L, U, rhs, schur, sinv_u;
    std::vector<int> piv;
    std::vector<double> e0, e1;  // two frames of defects (apply) or A^T A sums (linearise)
  };
  std::vector<double> frame_sm_, frame_sd_;  // per-frame squared residual norms
  std::vector<ThreadScratch> scratch_;
};

}  // namespace pliant::smoke
