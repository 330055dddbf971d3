// The deterministic mutation harness of the case parser and validation (CTest: fuzz_cases).
//
//   fuzz_cases [--seconds S] [--seed N] [--max-inputs K] [--save-defects DIR]
//
// Seeds: every case in cases/ (and the model files in models/ turned into inline-model cases
// when that directory exists) plus hand-made edge inputs. Each input is a seed changed by 1-4
// mutations drawn from a fixed-seed generator: byte flips, insertions and deletions, numbers
// replaced by extremes (0, -1, 1e308, 1e-320, nan, inf, 2^63, ...), lines duplicated, deleted or
// swapped, keys renamed, deep nesting, tables of another type. Runs until the time or input
// budget is spent; prints how many inputs it survived by outcome; exits 1 on the first defect
// (printing the input). With the same seed and budget in inputs (not seconds) the run is
// reproducible. For hours of coverage-guided fuzzing use scripts/fuzz.sh (libFuzzer, clang).
#include <algorithm>
#include <cctype>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <random>
#include <sstream>
#include <string>
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

std::vector<std::string> seeds() {
  std::vector<std::string> out;
  const fs::path root(PCSIM_SOURCE_DIR);
  std::vector<fs::path> files;
  for (const char* dir : {"cases", "tests/fuzz/corpus"}) {
    std::error_code ec;
    for (const auto& e : fs::directory_iterator(root / dir, ec))
      if (e.path().extension() == ".toml") files.push_back(e.path());
  }
  std::sort(files.begin(), files.end());  // directory order is not deterministic
  for (const auto& f : files) out.push_back(slurp(f));
  // Hand-made edges.
  out.push_back("");
  out.push_back("model = \"sieve\"\n");
  out.push_back("model = \"pendulum\"\n[initial]\nx = 1\ny = 0\n[solver]\nt_end = 1\n");
  out.push_back("model = \"slider_crank\"\n[constraints]\nB_y_copy = true\n");
  out.push_back("[output]\nsummary_periods = 9223372036854775807\n");
  out.push_back("[solver]\nrtol = 1e-300\natol = 1e-300\n");
  return out;
}

const std::vector<std::string>& extremes() {
  static const std::vector<std::string> v = {
      "0", "-0.0", "-1", "1e308", "-1e308", "1e-320", "nan", "inf", "-inf", "9223372036854775807",
      "-9223372036854775808", "18446744073709551616", "1e-9", "1e9", "0.5", "\"x\"", "true",
      "[]", "{}", "[1, 2]", "{ a = 1 }", "1979-05-27T07:32:00Z", "0x7fffffff", "1_000"};
  return v;
}

const std::vector<std::string>& keys() {
  static const std::vector<std::string> v = {
      "model", "name", "parameters", "initial", "constraints", "solver", "output", "m1", "omega",
      "t_end", "rtol", "dt", "summary_periods", "summary_time", "kernel", "form", "method",
      "contact", "rolling", "lock_theta", "rolling_as_printed", "s0", "added", "linear_algebra"};
  return v;
}

std::string mutate(std::string s, std::mt19937_64& rng) {
  auto pick = [&](std::size_t n) { return n == 0 ? 0 : static_cast<std::size_t>(rng() % n); };
  const int count = 1 + static_cast<int>(rng() % 4);
  for (int m = 0; m < count; ++m) {
    switch (rng() % 11) {
      case 0:  // flip a byte
        if (!s.empty()) s[pick(s.size())] ^= static_cast<char>(1u << (rng() % 8));
        break;
      case 1:  // insert a random printable byte
        s.insert(s.begin() + static_cast<long>(pick(s.size() + 1)), static_cast<char>(32 + rng() % 95));
        break;
      case 2:  // delete a span
        if (!s.empty()) {
          const std::size_t at = pick(s.size());
          s.erase(at, 1 + pick(std::min<std::size_t>(16, s.size() - at)));
        }
        break;
      case 3: {  // replace a number by an extreme
        std::vector<std::size_t> starts;
        for (std::size_t i = 0; i < s.size(); ++i)
          if ((std::isdigit(static_cast<unsigned char>(s[i])) || s[i] == '-') &&
              (i == 0 || s[i - 1] == ' ' || s[i - 1] == '='))
            starts.push_back(i);
        if (starts.empty()) break;
        const std::size_t at = starts[pick(starts.size())];
        std::size_t end = at;
        while (end < s.size() && s[end] != '\n' && s[end] != ' ' && s[end] != '#') ++end;
        s.replace(at, end - at, extremes()[pick(extremes().size())]);
        break;
      }
      case 4: {  // duplicate, delete or swap lines
        std::vector<std::string> lines;
        std::istringstream in(s);
        for (std::string l; std::getline(in, l);) lines.push_back(l);
        if (lines.empty()) break;
        const std::size_t a = pick(lines.size()), b = pick(lines.size());
        switch (rng() % 3) {
          case 0: lines.insert(lines.begin() + static_cast<long>(a), lines[b]); break;
          case 1: lines.erase(lines.begin() + static_cast<long>(a)); break;
          default: std::swap(lines[a], lines[b]); break;
        }
        s.clear();
        for (const auto& l : lines) s += l + "\n";
        break;
      }
      case 5:  // a key line with an extreme value
        s += "\n[" + keys()[pick(keys().size())] + "]\n" + keys()[pick(keys().size())] + " = " +
             extremes()[pick(extremes().size())] + "\n";
        break;
      case 6: {  // deep nesting, in a header or in a value
        const int depth = 1 + static_cast<int>(rng() % 64);
        std::string h = "[a";
        for (int i = 0; i < depth; ++i) h += ".a";
        if (rng() % 2) s += "\n" + h + "]\nx = 1\n";
        else s += "\nx = " + std::string(static_cast<std::size_t>(depth), '[') + std::string(static_cast<std::size_t>(depth), ']') + "\n";
        break;
      }
      case 7:  // an overriding model line
        s = "model = " + std::string(rng() % 2 ? "\"pendulum\"" : "\"../models/sieve_1995.toml\"") + "\n" + s;
        break;
      case 8:  // an added constraint with a random expression
        s += "\n[constraints.added]\nc" + std::to_string(rng() % 9) + " = \"" +
             std::string(rng() % 2 ? "s - 0.4" : "x^2 + y^2 - 1/0") + "\"\n";
        break;
      case 9:  // a random key in a known table
        s += "\n[" + keys()[1 + pick(6)] + "]\n" + keys()[pick(keys().size())] + "_" +
             std::to_string(rng() % 100) + " = 1\n";
        break;
      default:  // truncate
        if (!s.empty()) s.resize(pick(s.size()));
        break;
    }
  }
  return s;
}

}  // namespace

int main(int argc, char** argv) {
  double seconds = 10.0;
  unsigned long long seed = 1995, max_inputs = ~0ull;
  std::string save;
  for (int i = 1; i + 1 < argc; i += 2) {
    const std::string a = argv[i];
    if (a == "--seconds") seconds = std::atof(argv[i + 1]);
    else if (a == "--seed") seed = std::strtoull(argv[i + 1], nullptr, 10);
    else if (a == "--max-inputs") max_inputs = std::strtoull(argv[i + 1], nullptr, 10);
    else if (a == "--save-defects") save = argv[i + 1];
  }
  const auto corpus = seeds();
  std::mt19937_64 rng(seed);
  long counts[4] = {0, 0, 0, 0};
  double slowest = 0.0;
  std::string slowest_input;
  const auto start = std::chrono::steady_clock::now();
  unsigned long long n = 0;
  for (; n < max_inputs; ++n) {
    if (std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count() > seconds) break;
    // Every seed once as it is, then mutants.
    const std::string input = n < corpus.size() ? corpus[n] : mutate(corpus[rng() % corpus.size()], rng);
    std::string what;
    const auto t0 = std::chrono::steady_clock::now();
    const FuzzOutcome o = pcsim::testing::fuzz_case_input(input, &what);
    const double took = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    if (took > slowest) {
      slowest = took;
      slowest_input = input;
    }
    ++counts[static_cast<int>(o)];
    if (o == FuzzOutcome::defect) {
      std::printf("fuzz_cases: DEFECT on input %llu (seed %llu): %s\n----- input -----\n%s\n-----\n",
                  n, seed, what.c_str(), input.c_str());
      if (!save.empty()) std::ofstream(fs::path(save) / ("defect_" + std::to_string(n) + ".toml")) << input;
      return 1;
    }
  }
  std::printf("fuzz_cases: survived %llu inputs in %.0f s (seed %llu): %ld loaded and ran, %ld "
              "refused with a message, %ld numerical failures reported, 0 defects\n",
              n, std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count(),
              seed, counts[0], counts[1], counts[2]);
  if (std::getenv("PCSIM_FUZZ_SLOWEST"))
    std::printf("slowest input (%.2f s):\n%s\n", slowest, slowest_input.c_str());
  return 0;
}
