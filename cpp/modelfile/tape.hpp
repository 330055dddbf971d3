// The flat evaluation tape of a model file: straight-line code over an array of doubles
// ("slots"), with the values (run) and, in forward mode, k directional derivatives at once
// (run_tangent). Plain data, no GiNaC: built once by compile_tape (symbolic.hpp), then shared
// read-only by every thread.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <utility>
#include <vector>

namespace pcsim::modelfile {

/// One operation of the tape. Operands a, b are slots; dst is the result slot.
enum class Op : std::uint16_t {
  add,     ///< a + b
  sub,     ///< a - b
  mul,     ///< a * b
  div,     ///< a / b
  neg,     ///< -a
  recip,   ///< 1 / a
  sqr,     ///< a * a
  powi,    ///< a^k, k = the signed integer in b (|k| >= 3)
  pow,     ///< a^b
  sqrt,    ///< sqrt(a)
  sin, cos, tan, asin, acos, atan,
  atan2,   ///< atan2(a, b) (a the ordinate)
  sinh, cosh, tanh, exp, log,
  abs,     ///< |a|
  step,    ///< Heaviside: 0 (a < 0), 1/2 (a = 0), 1 (a > 0)
  min,     ///< min(a, b)
  max,     ///< max(a, b)
  sincos,  ///< dst = sin(a), b = cos(a): two results (b is the second result slot)
  madd,    ///< a * b + c   (fused from a mul whose only use is an add: one dispatch, not two;
  msub,    ///< a * b - c    rounded as the two operations, so the results are the same)
  nmadd,   ///< c - a * b
};

/// Name of an operation (for listings and messages).
const char* to_string(Op op);

struct Instr {
  Op op;
  std::uint32_t dst, a, b;
  std::uint32_t c = 0;  ///< third operand (madd, msub, nmadd)
};

/// Fuses, within one block, each mul whose only use is an add or sub of the same block into
/// a madd, msub or nmadd (results identical: the fused operations round as before). `keep`
/// marks slots that must still be written (results of the block).
void fuse_multiply_add(std::vector<Instr>& code, const std::vector<std::uint32_t>& keep);

/// Straight-line code computing some results, in dependency order, and the slots holding them
/// afterwards (a result may sit in the constant region, e.g. a constant entry of M).
struct Block {
  std::vector<Instr> code;
  std::vector<std::uint32_t> results;
};

/// The whole tape of a model. Slot layout:
///   [0, n_constant)        the constant region: literal numbers, parameters, hidden constants
///                          (from_initial constraints) and the prelude's results; written once
///                          per instantiation;
///   [n_constant, n_slots)  the state region: t, q, qd, qdd, R (n slots each, contiguous from
///                          state_input) and the state-dependent temporaries.
struct Tape {
  int n = 0;                          ///< coordinates
  std::uint32_t n_slots = 0, n_constant = 0;
  std::uint32_t zero_slot = 0;        ///< a literal 0 (structural zeros of results point here)
  std::vector<std::pair<std::uint32_t, double>> literals;
  std::vector<std::uint32_t> parameter_slots;  ///< by parameter index
  std::vector<std::uint32_t> hidden_slots;     ///< by hidden-constant index
  std::uint32_t t_slot = 0, q_slot = 0, qd_slot = 0, qdd_slot = 0, R_slot = 0;  ///< first of n
  /// The multipliers lambda_<constraint> (outputs only): n_lambda slots from lambda_slot.
  std::uint32_t lambda_slot = 0, n_lambda = 0;
  std::vector<Instr> prelude;         ///< everything that depends only on parameters
  std::vector<Block> blocks;          ///< the state-dependent code, one block per use

  /// Total instruction count of the blocks and the prelude (for listings and benchmarks).
  std::size_t instruction_count() const;
};

/// a^k for an integer k (|k| small): binary powering, as exact as repeated multiplication.
inline double powi(double a, int k) {
  unsigned e = static_cast<unsigned>(k < 0 ? -k : k);
  double result = 1.0, base = a;
  while (e != 0) {
    if (e & 1u) result *= base;
    base *= base;
    e >>= 1;
  }
  return k < 0 ? 1.0 / result : result;
}
/// Heaviside: 0 (a < 0), 1/2 (a = 0), 1 (a > 0).
inline double step(double a) { return a > 0 ? 1.0 : (a < 0 ? 0.0 : 0.5); }

/// A block compiled to native code at build time (tools/precompile_models: the built-in models
/// only): the same operations in the same order as run() performs, so the same results.
using NativeBlock = void (*)(double* v);

/// The operations of code as C++ statements on `double* v` (what a NativeBlock's body is).
std::string native_source(const std::vector<Instr>& code);

/// Runs code on the slot values v. No allocation, no exceptions.
void run(const Instr* code, std::size_t count, double* v);
inline void run(const std::vector<Instr>& code, double* v) { run(code.data(), code.size(), v); }

/// Runs code on the values v and their tangents d (k per slot, slot-major: d[slot * k + j]):
/// the forward mode of automatic differentiation on the tape. Slots that code does not write
/// keep their tangents (the caller seeds the inputs and zeroes the constant region).
void run_tangent(const Instr* code, std::size_t count, double* v, double* d, int k);
inline void run_tangent(const std::vector<Instr>& code, double* v, double* d, int k) {
  run_tangent(code.data(), code.size(), v, d, k);
}

/// A readable listing of a block (one instruction a line), for debugging and the docs.
std::string listing(const Tape& tape, const Block& block);

}  // namespace pcsim::modelfile
