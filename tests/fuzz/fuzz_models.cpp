// The deterministic mutation harness of model files and added constraints (CTest: fuzz_models).
//
//   fuzz_models [--seconds S] [--seed N] [--max-inputs K] [--input-seconds T] [--max-rss-mb M]
//               [--big-powers 0|1] [--save-defects DIR]
//
// An input is a case file with an inline model: one of the model files in models/ or a small
// pendulum, whose expressions (and names) are mutated with hostile text: calls with 0 to 3
// arguments of every function, deep nesting of parentheses, signs and calls (up to 10,000
// levels), huge and tiny exponents and literals (10^(10^10), (x+2)^(10^9), 1e-400), GiNaC's names
// (I, Pi, Euler, Catalan, D, ...), long names (up to 50,000 characters), bytes that are no
// operator, velocities inside functions in T, long sums, and added constraints
// ([constraints.added] NAME = "EXPR", the --constraint of the command line) of the same kinds.
// Each input is loaded and, if it loads, run for 2 ms of motion (tests/fuzz/case_fuzz.hpp).
// Expected outcomes: exit 0, 2 or 3 as the command line would give (loaded and ran, refused
// with a message, numerical failure). Anything else is a defect: an exception of no known kind,
// a crash, a sanitizer report, an input that takes longer than --input-seconds (default 2 s; CTest
// gives 4 s, 40 s under the sanitizers), or
// a peak resident memory above --max-rss-mb (default 2048) at the end. A watchdog ends the
// process, printing the input, if one input runs 10 times its budget (a runaway).
#include <sys/resource.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <condition_variable>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <mutex>
#include <random>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include "case_fuzz.hpp"

namespace fs = std::filesystem;
using pcsim::testing::FuzzOutcome;

namespace {

std::string slurp(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

const char* const kPendulum = R"TOML([model]
coordinates = ["x", "y"]
[model.parameters]
m = 1.0
L = 1.0
[model.define]
r2 = "x^2 + y^2"
[model.energy]
kinetic = "0.5*m*(x_d^2 + y_d^2)"
potential = "m*9.81*y"
[[model.constraint]]
name = "rod"
holonomic = "r2 - L^2"
[model.outputs]
tension = "-(R_x*x + R_y*y)/L"
[initial]
x = 1.0
)TOML";

std::vector<std::string> seeds() {
  std::vector<std::string> out = {kPendulum};
  std::vector<fs::path> files;
  std::error_code ec;
  for (const auto& e : fs::directory_iterator(fs::path(PCSIM_SOURCE_DIR) / "models", ec))
    if (e.path().extension() == ".toml") files.push_back(e.path());
  std::sort(files.begin(), files.end());
  for (const auto& f : files) out.push_back(slurp(f));
  return out;
}

const std::vector<std::string>& functions() {
  static const std::vector<std::string> v = {"sin", "cos",  "tan",  "asin", "acos", "atan",
                                             "atan2", "sinh", "cosh", "tanh", "exp", "log",
                                             "sqrt", "abs",  "pow",  "min",  "max", "foo", "D"};
  return v;
}

const std::vector<std::string>& odd_names() {
  static const std::vector<std::string> v = {
      "I", "Pi", "Euler", "Catalan", "D", "E", "Order", "zeta", "lgamma", "t", "pi", "x_d",
      "R_x", "x_dd", "residual_pos", "_", "a1", "1a", "sin", "heaviside", "min", "", "x y", "é"};
  return v;
}

std::string repeat(const std::string& s, std::size_t n) {
  std::string out;
  out.reserve(s.size() * n);
  for (std::size_t i = 0; i < n; ++i) out += s;
  return out;
}

// Legal powers above 3 of compound bases, such as (x^2 + y^2)^1000 or a ten-term sum^60: drawn by
// default since the tape stopped expanding polynomials and a kinetic energy of a high degree is
// refused from its structure (before, they took seconds to minutes); --big-powers 0 leaves them
// out. Exponents beyond the limit (refused at once) are always drawn.
bool g_big_powers = true;

class Gen {
 public:
  explicit Gen(std::mt19937_64& rng) : rng_(rng) {}

  // An exponent for a compound base.
  std::string exponent() {
    static const std::vector<std::string> special = {"1000", "1001", "-1000", "-1001", "0.5", "1/3", "(10^9)", "(10^(10^10))", "2", "60", "x", "1e-400"};
    if (coin(2)) {
      const std::string& e = special[pick(special.size())];
      if (!g_big_powers && (e == "1000" || e == "-1000" || e == "60")) return "61000";
      return e;
    }
    long n = static_cast<long>(pick(3001)) - 1500;
    if (!g_big_powers && std::labs(n) > 3 && std::labs(n) <= 1000) n += n > 0 ? 1000 : -1000;
    return std::to_string(n);
  }
  std::size_t pick(std::size_t n) { return n == 0 ? 0 : static_cast<std::size_t>(rng_() % n); }
  bool coin(int one_in) { return pick(static_cast<std::size_t>(one_in)) == 0; }

  std::string name() {
    switch (pick(6)) {
      case 0: return odd_names()[pick(odd_names().size())];
      case 1: return std::string(1 + pick(1 + (coin(4) ? 50000 : 200)), "abcxyz_"[pick(7)]);
      default: {
        static const std::vector<std::string> known = {"x", "y", "m", "L", "x_d", "y_d", "t", "pi", "r2", "s", "u", "theta"};
        return known[pick(known.size())];
      }
    }
  }

  std::string number() {
    static const std::vector<std::string> v = {
        "0", "1", "2", "0.5", "1e-400", "1e400", "1e308", "2.2250738585072014e-308", "4.9e-324",
        "1e-320", "9.8.1", ".", "1e", "1e+", "123456789012345678901234567890", "10^(10^10)",
        "(x+2)^(10^9)", "2^(2^(2^10))", "1000", "1001", "-1000", "0.001", "7"};
    return v[pick(v.size())];
  }

  // A random expression of bounded size, with hostile parts.
  std::string expr(int budget) {
    if (budget <= 0 || coin(3)) return coin(2) ? name() : number();
    switch (pick(12)) {
      case 0: {
        static const char* ops[] = {"+", "-", "*", "/", "^", "**", "%", ",", " ", "(", ")", "!", "'", "{", "#"};
        return expr(budget / 2) + ops[pick(15)] + expr(budget / 2);
      }
      case 1: {
        const std::string& f = functions()[pick(functions().size())];
        std::string args;
        const std::size_t n = pick(4);
        for (std::size_t i = 0; i < n; ++i) args += (i ? ", " : "") + expr(budget / 3);
        return f + "(" + args + ")";
      }
      case 2: {
        const std::size_t depth = coin(3) ? 1 + pick(10000) : 1 + pick(250);
        static const std::vector<std::pair<std::string, std::string>> nests = {
            {"(", ")"}, {"-", ""}, {"+", ""}, {"- ", ""}, {"sin(", ")"}, {"-(", ")"}, {"abs(", ")"}, {"pow(", ", 2)"}};
        const auto& n = nests[pick(nests.size())];
        return repeat(n.first, depth) + expr(budget / 2) + (coin(20) ? "" : repeat(n.second, depth));
      }
      case 3: return "(" + expr(budget / 2) + ")^(" + exponent() + ")";
      case 4: return "10^(10^" + std::to_string(pick(12)) + ")";
      case 5: return "(" + expr(budget / 2) + ")^(" + expr(budget / 2) + ")";
      case 6: return repeat("y+", pick(coin(5) ? 60000 : 100)) + "y";
      case 7: return "1e" + std::to_string(static_cast<long>(pick(800)) - 400);
      case 8: return functions()[pick(17)] + "(x_d + y)";
      case 9: return "pow(" + expr(budget / 2) + ", " + expr(budget / 2) + ")";
      case 10: return "min(" + expr(budget / 2) + ", max(" + expr(budget / 3) + ", " + expr(budget / 3) + "))";
      default: return expr(budget / 2) + (coin(2) ? "*" : "+") + expr(budget / 2);
    }
  }

 private:
  std::mt19937_64& rng_;
};

// The quoted strings of a TOML text: [begin, end) of their contents.
std::vector<std::pair<std::size_t, std::size_t>> strings_of(const std::string& s) {
  std::vector<std::pair<std::size_t, std::size_t>> out;
  for (std::size_t i = 0; i < s.size(); ++i) {
    if (s[i] == '#') {
      while (i < s.size() && s[i] != '\n') ++i;
      continue;
    }
    if (s[i] != '"') continue;
    const std::size_t b = i + 1;
    std::size_t e = b;
    while (e < s.size() && s[e] != '"' && s[e] != '\n') e += (s[e] == '\\' ? 2 : 1);
    if (e >= s.size() || s[e] != '"') break;
    out.push_back({b, e});
    i = e;
  }
  return out;
}

std::string escaped(const std::string& s) {
  std::string out;
  for (char c : s) {
    if (c == '"' || c == '\\') out += '\\';
    out += c;
  }
  return out;
}

std::string mutate(std::string s, std::mt19937_64& rng) {
  Gen g(rng);
  const int count = 1 + static_cast<int>(g.pick(3));
  for (int m = 0; m < count; ++m) {
    const auto strings = strings_of(s);
    const std::size_t k = strings.empty() ? 0 : g.pick(strings.size());
    const std::size_t b = strings.empty() ? 0 : strings[k].first, e = strings.empty() ? 0 : strings[k].second;
    switch (g.pick(9)) {
      case 0:  // replace an expression (or name) by a generated one
      case 1:
        if (!strings.empty()) s.replace(b, e - b, escaped(g.expr(8)));
        break;
      case 2:  // wrap it in a call, nesting or power
        if (!strings.empty()) {
          const std::string inner = s.substr(b, e - b);
          const std::string& f = functions()[g.pick(functions().size())];
          const std::string w = g.coin(2) ? f + "(" + inner + (g.coin(3) ? ", y" : "") + ")"
                                          : "(" + inner + ")^(" + escaped(g.exponent()) + ")";
          s.replace(b, e - b, w);
        }
        break;
      case 3:  // insert a token inside
        if (!strings.empty()) s.insert(b + g.pick(e - b + 1), escaped(g.coin(2) ? g.name() : g.number()));
        break;
      case 4:  // a velocity inside a function in T
        s += "\n";
        if (s.find("kinetic = \"") != std::string::npos) {
          const std::size_t p = s.find("kinetic = \"") + 11;
          s.insert(p, functions()[g.pick(17)] + "(" + (g.coin(2) ? "x_d" : "y_d") + ") + ");
        }
        break;
      case 5: {  // an added constraint (the command line's --constraint NAME=EXPR)
        s += "\n[constraints.added]\n\"" + escaped(g.name()) + "\" = \"" + escaped(g.expr(6)) + "\"\n";
        break;
      }
      case 6: {  // parameters or definitions with odd names
        const std::string n = g.name();
        if (s.find("[model.define]") != std::string::npos && g.coin(2)) {
          s.insert(s.find("[model.define]") + 14, "\n\"" + escaped(n) + "\" = \"" + escaped(g.expr(4)) + "\"");
        } else if (s.find("[model.parameters]") != std::string::npos) {
          s.insert(s.find("[model.parameters]") + 18, "\n\"" + escaped(n) + "\" = 2.5");
        }
        break;
      }
      case 7: {  // many coordinates
        const std::size_t p = s.find("coordinates = [");
        if (p != std::string::npos) {
          std::string more;
          const std::size_t n = g.coin(4) ? 10000 : g.pick(200);  // loads of 300+ coordinates take seconds
          for (std::size_t i = 0; i < n; ++i) more += "\"c" + std::to_string(i) + "\", ";
          s.insert(p + 15, more);
        }
        break;
      }
      default:  // a chain of definitions used by the potential (short: long chains are a
                // derivation-budget matter, not the parser's)
        if (s.find("[model.define]") != std::string::npos && s.find("potential = \"") != std::string::npos) {
          std::string chain;
          const std::size_t n = 1 + g.pick(6);
          for (std::size_t i = 1; i <= n; ++i)
            chain += "\nzz" + std::to_string(i) + " = \"" + (g.coin(2) ? "sin" : "abs") + "(zz" +
                     std::to_string(i - 1) + ") + zz" + std::to_string(i - 1) + "\"";
          s.insert(s.find("[model.define]") + 14, "\nzz0 = \"y\"" + chain);
          s.insert(s.find("potential = \"") + 13, "zz" + std::to_string(n) + " + ");
        }
        break;
    }
  }
  return s;
}

// Ends the process if one input runs far past its budget (a runaway would otherwise hang CTest
// until its timeout, without saying which input).
class Watchdog {
 public:
  Watchdog(double limit, std::string save) : limit_(limit), save_(std::move(save)), thread_([this] { loop(); }) {}
  ~Watchdog() {
    {
      std::lock_guard<std::mutex> l(m_);
      stop_ = true;
    }
    cv_.notify_all();
    thread_.join();
  }
  void start(const std::string* input, unsigned long long n) {
    std::lock_guard<std::mutex> l(m_);
    input_ = input;
    n_ = n;
    since_ = std::chrono::steady_clock::now();
  }
  void done() {
    std::lock_guard<std::mutex> l(m_);
    input_ = nullptr;
  }

 private:
  void loop() {
    std::unique_lock<std::mutex> l(m_);
    while (!stop_) {
      cv_.wait_for(l, std::chrono::milliseconds(200));
      if (input_ && std::chrono::duration<double>(std::chrono::steady_clock::now() - since_).count() > limit_) {
        std::printf("fuzz_models: DEFECT: input %llu ran more than %.0f s (a runaway)\n----- input (first 4000 bytes) -----\n%s\n-----\n",
                    n_, limit_, input_->substr(0, 4000).c_str());
        if (!save_.empty()) std::ofstream(fs::path(save_) / ("runaway_" + std::to_string(n_) + ".toml")) << *input_;
        std::fflush(stdout);
        std::_Exit(1);
      }
    }
  }
  double limit_;
  std::string save_;
  unsigned long long n_ = 0;
  std::mutex m_;
  std::condition_variable cv_;
  bool stop_ = false;
  const std::string* input_ = nullptr;
  std::chrono::steady_clock::time_point since_;
  std::thread thread_;
};

}  // namespace

int main(int argc, char** argv) {
  double seconds = 10.0, input_seconds = 2.0, max_rss_mb = 2048.0;
  unsigned long long seed = 19, max_inputs = ~0ull;
  std::string save;
  for (int i = 1; i + 1 < argc; i += 2) {
    const std::string a = argv[i];
    if (a == "--seconds") seconds = std::atof(argv[i + 1]);
    else if (a == "--seed") seed = std::strtoull(argv[i + 1], nullptr, 10);
    else if (a == "--max-inputs") max_inputs = std::strtoull(argv[i + 1], nullptr, 10);
    else if (a == "--input-seconds") input_seconds = std::atof(argv[i + 1]);
    else if (a == "--max-rss-mb") max_rss_mb = std::atof(argv[i + 1]);
    else if (a == "--big-powers") g_big_powers = std::string(argv[i + 1]) == "1";
    else if (a == "--save-defects") save = argv[i + 1];
  }
  const auto corpus = seeds();
  std::mt19937_64 rng(seed);
  long counts[4] = {0, 0, 0, 0};
  double slowest = 0.0;
  std::string slowest_input;
  Watchdog watchdog(10.0 * input_seconds, save);
  const auto start = std::chrono::steady_clock::now();
  unsigned long long n = 0;
  for (; n < max_inputs; ++n) {
    if (std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count() > seconds) break;
    const std::string input = n < corpus.size() ? corpus[n] : mutate(corpus[rng() % corpus.size()], rng);
    std::string what;
    watchdog.start(&input, n);
    const auto t0 = std::chrono::steady_clock::now();
    const FuzzOutcome o = pcsim::testing::fuzz_case_input(input, &what);
    const double took = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    watchdog.done();
    if (took > slowest) {
      slowest = took;
      slowest_input = input;
    }
    ++counts[static_cast<int>(o)];
    if (o == FuzzOutcome::defect || took > input_seconds) {
      std::printf("fuzz_models: DEFECT on input %llu (seed %llu): %s\n----- input (first 4000 bytes) -----\n%s\n-----\n",
                  n, seed, o == FuzzOutcome::defect ? what.c_str() : ("took " + std::to_string(took) + " s").c_str(),
                  input.substr(0, 4000).c_str());
      if (!save.empty()) std::ofstream(fs::path(save) / ("defect_" + std::to_string(n) + ".toml")) << input;
      return 1;
    }
  }
  rusage ru{};
  getrusage(RUSAGE_SELF, &ru);
  const double rss_mb = static_cast<double>(ru.ru_maxrss) / 1024.0;
  std::printf("fuzz_models: survived %llu inputs in %.0f s (seed %llu): %ld loaded and ran (exit 0), %ld "
              "refused with a message (exit 2), %ld numerical failures (exit 3), 0 defects; slowest "
              "input %.3f s, peak memory %.0f MB\n",
              n, std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count(), seed,
              counts[0], counts[1], counts[2], slowest, rss_mb);
  if (std::getenv("PCSIM_FUZZ_SLOWEST")) std::printf("slowest input:\n%s\n", slowest_input.substr(0, 4000).c_str());
  if (rss_mb > max_rss_mb) {
    std::printf("fuzz_models: DEFECT: peak memory %.0f MB above %.0f MB\n", rss_mb, max_rss_mb);
    return 1;
  }
  return 0;
}
