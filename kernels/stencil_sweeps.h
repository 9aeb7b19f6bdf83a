#pragma once
// Whole-field sweeps over a StencilOperator (kernels/stencil_operator.h), shared by the linear
// solvers: y = A x, residual, Jacobi, red-black Gauss-Seidel. The loops run over rows with row
// pointers; the first and last cell of a row take the (periodic or weight-0) edge neighbours
// separately so the middle of the row vectorises. No halo of x is read.
//
// Each sweep runs its rows on a RowExecutor (runtime/row_executor.h): every row is written by
// one band, and reductions add per-row partials in row order, so the result is the same bits
// on any back end and any number of workers. The default is the serial executor.
#include <cstdint>
#include <vector>

#include "kernels/stencil_operator.h"
#include "runtime/row_executor.h"

namespace ardcell::stencil {

// The rows of an operator whose middle cells (1 .. nx - 2) share one diagonal and one weight on
// all four faces: an isotropic operator away from the domain's edges and solid cells. A sweep
// over such a row multiplies by those two numbers instead of reading four coefficient arrays -
// the same operations in the same order (this file is built without contracting products into
// fused multiply-adds), so the same bits. analyse() after every change of the operator.
class UniformRows {
 public:
  explicit UniformRows(int rows)
      : diag_(std::size_t(rows)), weight_(std::size_t(rows)), uniform_(std::size_t(rows)) {}
  void analyse(const StencilOperator& op, RowExecutor& ex = RowExecutor::serial());
  bool uniform(int j) const { return uniform_[std::size_t(j)] != 0; }
  float diag(int j) const { return diag_[std::size_t(j)]; }
  float weight(int j) const { return weight_[std::size_t(j)]; }

 private:
  std::vector<float> diag_, weight_;
  std::vector<uint8_t> uniform_;
};

// x_out = D^-1 (b + (D - A) x_in) over the interior. x_in and x_out must differ. With `uniform`
// (analysed for this operator), its uniform rows skip the coefficient arrays. On a block
// operator (assemble_block_operator) over the block's cells, reading x_in's halo (exchanged) for
// the neighbouring blocks' cells: each cell the whole grid's sweep's bits. A non-empty `region`
// (inside the operator's cells) computes only those cells: a block's inner cells, which read no
// halo, while the exchange is in flight, then the ring along its edges.
void jacobi_sweep(const StencilOperator& op, const FieldF& b, const FieldF& x_in, FieldF& x_out,
                  RowExecutor& ex = RowExecutor::serial(), const UniformRows* uniform = nullptr,
                  Box2 region = {});

// Ghost-zone temporal blocking of Jacobi sweeps (seed 000, Jacobi being the real-time default):
// `sweeps` sweeps from x_in into x_out in ONE pass over the grid, the same bits as `sweeps`
// jacobi_sweep calls ping-ponging between two fields. The rows are cut into one band per worker;
// a band computes the intermediate sweeps of its rows grown by the sweeps still to come (the
// dependency cone) in rings of three rows per sweep held in cache, and writes only its own rows
// of x_out, so no band waits for another and nothing but the result goes back to memory. The
// cost is the cones' overlap: about sweeps^2 rows recomputed per band boundary.
// With `norms`, the same pass also returns |b - A x_out|^2 and |b|^2, with the bits of
// residual() and norm2_squared() (a solve's residual report without another pass).
// x_in and x_out must differ. Scratch is allocated at construction; sweeps() allocates nothing.
class JacobiBlocking {
 public:
  static constexpr int kMaxSweeps = 32;
  struct Norms {
    double residual2 = 0.0;  // |b - A x_out|^2
    double rhs2 = 0.0;       // |b|^2
  };
  JacobiBlocking(Int2 size, int bands);
  void sweeps(const StencilOperator& op, const FieldF& b, const FieldF& x_in, FieldF& x_out,
              int sweeps, RowExecutor& ex = RowExecutor::serial(),
              const UniformRows* uniform = nullptr, Norms* norms = nullptr);

 private:
  void band(const StencilOperator& op, const FieldF& b, const FieldF& x_in, FieldF& x_out,
            int sweeps, int y0, int y1, float* rings, const UniformRows* uniform, bool norms) const;
  Int2 size_;
  int bands_;
  std::size_t row_stride_;
  std::vector<float> rings_;
  // Per-row partials of the norms, added in row order as RowExecutor::sum_rows does.
  mutable std::vector<double> residual_rows_, rhs_rows_;
};

// One red-black Gauss-Seidel sweep in place: cells with (x + y) even, then odd. On a block
// operator, each half over the block's cells (global x + y), reading x's halo: exchange it after
// each half; a grid that wraps an odd number of cells along an axis cannot be cut so (its order
// across the wrap is the whole grid's).
void rbgs_sweep(const StencilOperator& op, const FieldF& b, FieldF& x,
                RowExecutor& ex = RowExecutor::serial());
// Half a sweep: only the cells with (x + y) % 2 == color (of `region`, as jacobi_sweep's).
void rbgs_half_sweep(const StencilOperator& op, const FieldF& b, FieldF& x, int color,
                     RowExecutor& ex = RowExecutor::serial(), Box2 region = {});

// r = b - A x (when r is not null); returns |b - A x|_2^2 accumulated in double. On a block
// operator, over the block's cells (its rows' partials in row order).
double residual(const StencilOperator& op, const FieldF& b, const FieldF& x, FieldF* r,
                RowExecutor& ex = RowExecutor::serial());
// r = b - A x alone (a multigrid cycle's restriction needs no norm): residual()'s r, bit for bit.
void residual_field(const StencilOperator& op, const FieldF& b, const FieldF& x, FieldF& r,
                    RowExecutor& ex = RowExecutor::serial());

// Sum of squares over the interior (a block's, on a block), in double.
double norm2_squared(const FieldF& f, RowExecutor& ex = RowExecutor::serial());

// The constant null space of singular operators (pure Neumann or periodic Poisson, possibly
// with isolated solid cells): Z = cells whose row sums to zero. When every other cell is
// decoupled from Z, A is singular with null vector 1 on Z, and A x = b is solvable only when
// b sums to zero over Z. Computed once per prepare(); uses no heap after construction.
class NullSpace {
 public:
  explicit NullSpace(Int2 size) : in_null_(size, 0) {}
  void analyse(const StencilOperator& op, RowExecutor& ex = RowExecutor::serial());
  bool singular() const { return singular_; }
  const Field<uint8_t>& mask() const { return in_null_; }  // 1 = cell of Z
  int64_t count() const { return count_; }
  // Subtracts the mean over Z from the cells of Z (no-op when not singular).
  void remove_mean(FieldF& f, RowExecutor& ex = RowExecutor::serial()) const;
  // |f|^2 without its component along the null vector (|f|^2 when not singular).
  double consistent_norm2(const FieldF& f, RowExecutor& ex = RowExecutor::serial()) const;
  // The same from |f|^2 already known (`all`, e.g. residual()'s return).
  double consistent_part(double all, const FieldF& f, RowExecutor& ex) const;

 private:
  double null_sum(const FieldF& f, RowExecutor& ex) const;  // sum of f over Z, row order
  Field<uint8_t> in_null_;
  bool singular_ = false;
  int64_t count_ = 0;
};

}  // namespace ardcell::stencil
