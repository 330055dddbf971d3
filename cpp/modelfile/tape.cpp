// The tape interpreter: values and forward-mode tangents (see tape.hpp).
#include "modelfile/tape.hpp"

#include <cstdio>

#include <cmath>
#include <sstream>
#include <unordered_map>

namespace pcsim::modelfile {

const char* to_string(Op op) {
  switch (op) {
    case Op::add: return "add";
    case Op::sub: return "sub";
    case Op::mul: return "mul";
    case Op::div: return "div";
    case Op::neg: return "neg";
    case Op::recip: return "recip";
    case Op::sqr: return "sqr";
    case Op::powi: return "powi";
    case Op::pow: return "pow";
    case Op::sqrt: return "sqrt";
    case Op::sin: return "sin";
    case Op::cos: return "cos";
    case Op::tan: return "tan";
    case Op::asin: return "asin";
    case Op::acos: return "acos";
    case Op::atan: return "atan";
    case Op::atan2: return "atan2";
    case Op::sinh: return "sinh";
    case Op::cosh: return "cosh";
    case Op::tanh: return "tanh";
    case Op::exp: return "exp";
    case Op::log: return "log";
    case Op::abs: return "abs";
    case Op::step: return "step";
    case Op::min: return "min";
    case Op::max: return "max";
    case Op::sincos: return "sincos";
    case Op::madd: return "madd";
    case Op::msub: return "msub";
    case Op::nmadd: return "nmadd";
  }
  return "?";
}

std::size_t Tape::instruction_count() const {
  std::size_t count = prelude.size();
  for (const Block& b : blocks) count += b.code.size();
  return count;
}

namespace {

inline double sign(double a) { return a > 0 ? 1.0 : (a < 0 ? -1.0 : 0.0); }

}  // namespace

std::string native_source(const std::vector<Instr>& code) {
  std::string out;
  char buf[160];
  auto v = [](std::uint32_t slot) { return "v[" + std::to_string(slot) + "]"; };
  for (const Instr& in : code) {
    const std::string d = v(in.dst), a = v(in.a), b = v(in.b), c = v(in.c);
    std::string e;
    switch (in.op) {
      case Op::add: e = a + " + " + b; break;
      case Op::sub: e = a + " - " + b; break;
      case Op::mul: e = a + " * " + b; break;
      case Op::div: e = a + " / " + b; break;
      case Op::neg: e = "-" + a; break;
      case Op::recip: e = "1.0 / " + a; break;
      case Op::sqr: e = a + " * " + a; break;
      case Op::powi: e = "pcsim::modelfile::powi(" + a + ", " + std::to_string(static_cast<std::int32_t>(in.b)) + ")"; break;
      case Op::pow: e = "std::pow(" + a + ", " + b + ")"; break;
      case Op::sqrt: e = "std::sqrt(" + a + ")"; break;
      case Op::sin: e = "std::sin(" + a + ")"; break;
      case Op::cos: e = "std::cos(" + a + ")"; break;
      case Op::tan: e = "std::tan(" + a + ")"; break;
      case Op::asin: e = "std::asin(" + a + ")"; break;
      case Op::acos: e = "std::acos(" + a + ")"; break;
      case Op::atan: e = "std::atan(" + a + ")"; break;
      case Op::atan2: e = "std::atan2(" + a + ", " + b + ")"; break;
      case Op::sinh: e = "std::sinh(" + a + ")"; break;
      case Op::cosh: e = "std::cosh(" + a + ")"; break;
      case Op::tanh: e = "std::tanh(" + a + ")"; break;
      case Op::exp: e = "std::exp(" + a + ")"; break;
      case Op::log: e = "std::log(" + a + ")"; break;
      case Op::abs: e = "std::abs(" + a + ")"; break;
      case Op::step: e = "pcsim::modelfile::step(" + a + ")"; break;
      case Op::min: e = "std::fmin(" + a + ", " + b + ")"; break;
      case Op::max: e = "std::fmax(" + a + ", " + b + ")"; break;
      case Op::sincos:
        std::snprintf(buf, sizeof buf, "  { const double x = %s; %s = std::sin(x); %s = std::cos(x); }\n",
                      a.c_str(), d.c_str(), b.c_str());
        out += buf;
        continue;
      case Op::madd: e = a + " * " + b + " + " + c; break;
      case Op::msub: e = a + " * " + b + " - " + c; break;
      case Op::nmadd: e = c + " - " + a + " * " + b; break;
    }
    out += "  " + d + " = " + e + ";\n";
  }
  return out;
}

void run(const Instr* code, std::size_t count, double* v) {
  const Instr* const end = code + count;
  for (const Instr* in = code; in != end; ++in) {
    const double a = v[in->a];
    double& y = v[in->dst];
    switch (in->op) {
      case Op::add: y = a + v[in->b]; break;
      case Op::sub: y = a - v[in->b]; break;
      case Op::mul: y = a * v[in->b]; break;
      case Op::div: y = a / v[in->b]; break;
      case Op::neg: y = -a; break;
      case Op::recip: y = 1.0 / a; break;
      case Op::sqr: y = a * a; break;
      case Op::powi: y = powi(a, static_cast<int>(static_cast<std::int32_t>(in->b))); break;
      case Op::pow: y = std::pow(a, v[in->b]); break;
      case Op::sqrt: y = std::sqrt(a); break;
      case Op::sin: y = std::sin(a); break;
      case Op::cos: y = std::cos(a); break;
      case Op::tan: y = std::tan(a); break;
      case Op::asin: y = std::asin(a); break;
      case Op::acos: y = std::acos(a); break;
      case Op::atan: y = std::atan(a); break;
      case Op::atan2: y = std::atan2(a, v[in->b]); break;
      case Op::sinh: y = std::sinh(a); break;
      case Op::cosh: y = std::cosh(a); break;
      case Op::tanh: y = std::tanh(a); break;
      case Op::exp: y = std::exp(a); break;
      case Op::log: y = std::log(a); break;
      case Op::abs: y = std::abs(a); break;
      case Op::step: y = step(a); break;
      case Op::min: y = std::fmin(a, v[in->b]); break;
      case Op::max: y = std::fmax(a, v[in->b]); break;
      case Op::sincos:
        y = std::sin(a);
        v[in->b] = std::cos(a);
        break;
      case Op::madd: y = a * v[in->b] + v[in->c]; break;
      case Op::msub: y = a * v[in->b] - v[in->c]; break;
      case Op::nmadd: y = v[in->c] - a * v[in->b]; break;
    }
  }
}

void run_tangent(const Instr* code, std::size_t count, double* v, double* d, int k) {
  const Instr* const end = code + count;
  for (const Instr* in = code; in != end; ++in) {
    const double a = v[in->a];
    const double* da = d + static_cast<std::size_t>(in->a) * k;
    double* dy = d + static_cast<std::size_t>(in->dst) * k;
    double& y = v[in->dst];
    // Operations with a second operand read it (and its tangents) only where they have one.
    auto B = [&] { return v[in->b]; };
    auto dB = [&] { return d + static_cast<std::size_t>(in->b) * k; };
    switch (in->op) {
      case Op::add: {
        const double* db = dB();
        y = a + B();
        for (int j = 0; j < k; ++j) dy[j] = da[j] + db[j];
        break;
      }
      case Op::sub: {
        const double* db = dB();
        y = a - B();
        for (int j = 0; j < k; ++j) dy[j] = da[j] - db[j];
        break;
      }
      case Op::mul: {
        const double* db = dB();
        const double b = B();
        y = a * b;
        for (int j = 0; j < k; ++j) dy[j] = da[j] * b + a * db[j];
        break;
      }
      case Op::div: {
        const double* db = dB();
        const double b = B();
        y = a / b;
        for (int j = 0; j < k; ++j) dy[j] = (da[j] - y * db[j]) / b;
        break;
      }
      case Op::neg:
        y = -a;
        for (int j = 0; j < k; ++j) dy[j] = -da[j];
        break;
      case Op::recip: {
        y = 1.0 / a;
        const double c = -y * y;
        for (int j = 0; j < k; ++j) dy[j] = c * da[j];
        break;
      }
      case Op::sqr: {
        y = a * a;
        const double c = 2.0 * a;
        for (int j = 0; j < k; ++j) dy[j] = c * da[j];
        break;
      }
      case Op::powi: {
        const int e = static_cast<int>(static_cast<std::int32_t>(in->b));
        const double p = powi(a, e - 1);  // a^(e-1): finite at a = 0 for e >= 1
        y = p * a;
        const double c = e * p;
        for (int j = 0; j < k; ++j) dy[j] = c * da[j];
        break;
      }
      case Op::pow: {
        const double* db = dB();
        const double b = B();
        y = std::pow(a, b);
        const double c = b * std::pow(a, b - 1.0);
        for (int j = 0; j < k; ++j) {
          // The exponent's tangent is usually 0 (a constant exponent): then log(a) is not
          // needed, and must not be formed (a < 0 would give NaN * 0).
          dy[j] = c * da[j] + (db[j] != 0.0 ? y * std::log(a) * db[j] : 0.0);
        }
        break;
      }
      case Op::sqrt: {
        y = std::sqrt(a);
        const double c = 0.5 / y;
        for (int j = 0; j < k; ++j) dy[j] = c * da[j];
        break;
      }
      case Op::sin: {
        y = std::sin(a);
        const double c = std::cos(a);
        for (int j = 0; j < k; ++j) dy[j] = c * da[j];
        break;
      }
      case Op::cos: {
        y = std::cos(a);
        const double c = -std::sin(a);
        for (int j = 0; j < k; ++j) dy[j] = c * da[j];
        break;
      }
      case Op::tan: {
        y = std::tan(a);
        const double c = 1.0 + y * y;
        for (int j = 0; j < k; ++j) dy[j] = c * da[j];
        break;
      }
      case Op::asin: {
        y = std::asin(a);
        const double c = 1.0 / std::sqrt(1.0 - a * a);
        for (int j = 0; j < k; ++j) dy[j] = c * da[j];
        break;
      }
      case Op::acos: {
        y = std::acos(a);
        const double c = -1.0 / std::sqrt(1.0 - a * a);
        for (int j = 0; j < k; ++j) dy[j] = c * da[j];
        break;
      }
      case Op::atan: {
        y = std::atan(a);
        const double c = 1.0 / (1.0 + a * a);
        for (int j = 0; j < k; ++j) dy[j] = c * da[j];
        break;
      }
      case Op::atan2: {
        const double* db = dB();
        const double b = B();
        y = std::atan2(a, b);
        const double r2 = a * a + b * b;
        for (int j = 0; j < k; ++j) dy[j] = (b * da[j] - a * db[j]) / r2;
        break;
      }
      case Op::sinh: {
        y = std::sinh(a);
        const double c = std::cosh(a);
        for (int j = 0; j < k; ++j) dy[j] = c * da[j];
        break;
      }
      case Op::cosh: {
        y = std::cosh(a);
        const double c = std::sinh(a);
        for (int j = 0; j < k; ++j) dy[j] = c * da[j];
        break;
      }
      case Op::tanh: {
        y = std::tanh(a);
        const double c = 1.0 - y * y;
        for (int j = 0; j < k; ++j) dy[j] = c * da[j];
        break;
      }
      case Op::exp: {
        y = std::exp(a);
        for (int j = 0; j < k; ++j) dy[j] = y * da[j];
        break;
      }
      case Op::log: {
        y = std::log(a);
        for (int j = 0; j < k; ++j) dy[j] = da[j] / a;
        break;
      }
      case Op::abs: {
        y = std::abs(a);
        const double c = sign(a);
        for (int j = 0; j < k; ++j) dy[j] = c * da[j];
        break;
      }
      case Op::step:
        y = step(a);
        for (int j = 0; j < k; ++j) dy[j] = 0.0;
        break;
      case Op::min: {
        const double* db = dB();
        const double b = B();
        y = std::fmin(a, b);
        const double* src = a <= b ? da : db;
        for (int j = 0; j < k; ++j) dy[j] = src[j];
        break;
      }
      case Op::max: {
        const double* db = dB();
        const double b = B();
        y = std::fmax(a, b);
        const double* src = a >= b ? da : db;
        for (int j = 0; j < k; ++j) dy[j] = src[j];
        break;
      }
      case Op::sincos: {
        const double s = std::sin(a), c = std::cos(a);
        y = s;
        v[in->b] = c;
        double* dc = dB();
        for (int j = 0; j < k; ++j) {
          dy[j] = c * da[j];
          dc[j] = -s * da[j];
        }
        break;
      }
      case Op::madd:
      case Op::msub:
      case Op::nmadd: {
        const double* db = dB();
        const double* dc = d + static_cast<std::size_t>(in->c) * k;
        const double b = B(), c = v[in->c];
        const double sc = in->op == Op::msub ? -1.0 : 1.0;  // sign of c
        const double sp = in->op == Op::nmadd ? -1.0 : 1.0;  // sign of the product
        y = in->op == Op::madd ? a * b + c : (in->op == Op::msub ? a * b - c : c - a * b);
        for (int j = 0; j < k; ++j) dy[j] = sp * (da[j] * b + a * db[j]) + sc * dc[j];
        break;
      }
    }
  }
}

void fuse_multiply_add(std::vector<Instr>& code, const std::vector<std::uint32_t>& keep) {
  // Uses of each slot within the block (operands, and the block's results).
  std::unordered_map<std::uint32_t, int> uses;
  std::unordered_map<std::uint32_t, std::size_t> defined_by;  // slot -> index of its mul
  for (std::uint32_t r : keep) uses[r] += 2;  // never fuse away a result
  for (std::size_t i = 0; i < code.size(); ++i) {
    const Instr& in = code[i];
    ++uses[in.a];
    switch (in.op) {
      case Op::add: case Op::sub: case Op::mul: case Op::div: case Op::pow: case Op::atan2:
      case Op::min: case Op::max:
        ++uses[in.b];
        break;
      case Op::sincos:
        uses[in.b] += 2;  // its second result: never a fusable product
        break;
      default: break;
    }
    if (in.op == Op::mul) defined_by[in.dst] = i;
  }
  std::vector<char> drop(code.size(), 0);
  for (Instr& in : code) {
    if (in.op != Op::add && in.op != Op::sub) continue;
    auto fusable = [&](std::uint32_t slot) {
      auto it = defined_by.find(slot);
      return it != defined_by.end() && !drop[it->second] && uses[slot] == 1;
    };
    const bool left = fusable(in.a), right = fusable(in.b);
    if (!left && !right) continue;
    const std::size_t k = defined_by[left ? in.a : in.b];
    const Instr product = code[k];
    const std::uint32_t other = left ? in.b : in.a;
    if (in.op == Op::add) {
      in.op = Op::madd;
    } else {
      in.op = left ? Op::msub : Op::nmadd;
    }
    in.a = product.a;
    in.b = product.b;
    in.c = other;
    drop[k] = 1;
  }
  std::size_t out = 0;
  for (std::size_t i = 0; i < code.size(); ++i) {
    if (!drop[i]) code[out++] = code[i];
  }
  code.resize(out);
}

std::string listing(const Tape& tape, const Block& block) {
  std::ostringstream os;
  auto slot = [&](std::uint32_t s) { return (s < tape.n_constant ? "c" : "s") + std::to_string(s); };
  for (const Instr& in : block.code) {
    os << slot(in.dst) << " = " << to_string(in.op) << " " << slot(in.a);
    if (in.op == Op::powi) {
      os << " " << static_cast<std::int32_t>(in.b);
    } else if (in.op == Op::sub || in.op == Op::add || in.op == Op::mul || in.op == Op::div ||
               in.op == Op::pow || in.op == Op::atan2 || in.op == Op::min || in.op == Op::max ||
               in.op == Op::sincos) {
      os << " " << slot(in.b);
    } else if (in.op == Op::madd || in.op == Op::msub || in.op == Op::nmadd) {
      os << " " << slot(in.b) << " " << slot(in.c);
    }
    os << "\n";
  }
  os << "results:";
  for (std::uint32_t r : block.results) os << " " << slot(r);
  os << "\n";
  return os.str();
}

}  // namespace pcsim::modelfile
