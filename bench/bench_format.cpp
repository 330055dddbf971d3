// The time-series formatter, old against new in the same process: std::to_chars appended field
// by field to a std::string (the writer before issue 23) against common/format.hpp's
// write_number into a row buffer appended once per row (the writer now). Both produce the same
// bytes (checked here on every row, and tests/common/test_format checks round trip and shortness).
// Data: rows shaped as the sieve's (22 columns: a time on a 1e-3 grid, zeros, a constant, and
// smooth signals of magnitudes 1e-19..1e2), and numbers uniform in their bits' logarithm.
// Then the binary form of output.format = "npy" (issue 23): each number's 8 bytes appended (what
// the writer does then), and the whole writer (sim::RowWriter on its thread, into a file in the
// temporary directory, closed with its fsync) for both formats, CSV against NPY.
// Usage: bench_format [--verify N]   (N random doubles checked against std::to_chars, no timing)
#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <random>
#include <string>
#include <vector>

#include <fcntl.h>
#include <unistd.h>

#include <chrono>
#include <filesystem>

#include "bench_timing.hpp"
#include "common/files.hpp"
#include "common/format.hpp"
#include "sim/row_writer.hpp"

namespace {

constexpr int kColumns = 22;
constexpr int kRows = 10001;

std::vector<double> sieve_like_rows() {
  std::vector<double> v;
  v.reserve(static_cast<std::size_t>(kRows) * kColumns);
  std::mt19937_64 rng(1995);
  std::uniform_real_distribution<double> u(-1, 1);
  for (int r = 0; r < kRows; ++r) {
    const double t = r * 1e-3;
    v.push_back(t);
    for (int j = 1; j < kColumns; ++j) {
      if (j == 5) v.push_back(0.15);
      else if (j >= 13 && j <= 15) v.push_back(0.0);
      else v.push_back(std::pow(10.0, -(j % 20)) * std::sin(280 * t + j) * (1 + 1e-3 * u(rng)));
    }
  }
  return v;
}

void old_rows(const std::vector<double>& v, std::string& text) {
  text.clear();
  for (std::size_t i = 0; i < v.size(); i += kColumns) {
    for (int j = 0; j < kColumns; ++j) {
      if (j) text += ',';
      char buf[40];
      const auto r = std::to_chars(buf, buf + sizeof buf, v[i + static_cast<std::size_t>(j)]);
      text.append(buf, r.ptr);
    }
    text += '\n';
  }
}

void new_rows(const std::vector<double>& v, std::string& text) {
  text.clear();
  char line[kColumns * (pcsim::kMaxNumberChars + 1) + 1];
  for (std::size_t i = 0; i < v.size(); i += kColumns) {
    char* p = line;
    for (int j = 0; j < kColumns; ++j) {
      if (j) *p++ = ',';
      p = pcsim::write_csv_number(p, v[i + static_cast<std::size_t>(j)]);
    }
    *p++ = '\n';
    text.append(line, p);
  }
}

void npy_rows(const std::vector<double>& v, std::string& bytes) {
  bytes.clear();
  for (std::size_t i = 0; i < v.size(); i += kColumns)
    bytes.append(reinterpret_cast<const char*>(v.data() + i), kColumns * sizeof(double));
}

// The whole writer: rows handed to sim::RowWriter, formatted (or copied) on its thread, written
// to a file and fsynced by finish(). Wall seconds, best of `repeats`.
double writer_seconds(const std::vector<double>& v, bool npy, int repeats) {
  const std::filesystem::path f = std::filesystem::temp_directory_path() /
                                  ("pcsim_bench_writer_" + std::to_string(::getpid()) + (npy ? ".npy" : ".csv"));
  double best = 1e300;
  for (int r = 0; r < repeats; ++r) {
    const int fd = ::open(f.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
    if (fd < 0) return -1.0;
    pcsim::OutputStream out(fd, f);
    const auto t0 = std::chrono::steady_clock::now();
    {
      std::vector<std::string> names;
      for (int j = 0; j < kColumns; ++j) names.push_back("c" + std::to_string(j));
      auto w = npy ? std::make_unique<pcsim::sim::RowWriter>(out, kColumns, 0, std::vector<std::string>{},
                                                             pcsim::sim::RowWriter::Npy{names})
                   : std::make_unique<pcsim::sim::RowWriter>(out, kColumns);
      for (std::size_t i = 0; i < v.size(); i += kColumns) w->add(v.data() + i);
      w->finish();
    }
    best = std::min(best, std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
  }
  std::filesystem::remove(f);
  return best;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc == 3 && std::string(argv[1]) == "--verify") {
    const long n = std::atol(argv[2]);
    std::mt19937_64 rng(static_cast<std::uint64_t>(n));
    long bad = 0;
    for (long i = 0; i < n; ++i) {
      const std::uint64_t b = rng();
      double x;
      std::memcpy(&x, &b, 8);
      char a[64], c[64];
      const auto r = std::to_chars(a, a + 64, x);
      char* e = pcsim::write_number(c, x);
      if (r.ptr - a != e - c || std::memcmp(a, c, static_cast<std::size_t>(e - c)) != 0) {
        if (++bad <= 5) std::printf("mismatch: %.*s vs %.*s\n", int(r.ptr - a), a, int(e - c), c);
      }
    }
    std::printf("verify: %ld random doubles, %ld mismatches against std::to_chars\n", n, bad);
    return bad ? 1 : 0;
  }
  const std::vector<double> rows = sieve_like_rows();
  std::string a, b;
  old_rows(rows, a);
  new_rows(rows, b);
  if (a != b) {
    std::printf("bench_format: the two writers differ\n");
    return 1;
  }
  const double t_old = pcsim_bench::seconds_per_call([&] { old_rows(rows, a); }, 5, 1);
  const double t_new = pcsim_bench::seconds_per_call([&] { new_rows(rows, b); }, 5, 1);
  const double n = static_cast<double>(rows.size());
  std::printf("sieve-shaped rows (%d x %d, %zu bytes):\n", kRows, kColumns, b.size());
  std::printf("  old (std::to_chars, append per field): %.2f ms  %.1f ns/number\n", 1e3 * t_old, 1e9 * t_old / n);
  std::printf("  new (write_number, append per row):    %.2f ms  %.1f ns/number\n", 1e3 * t_new, 1e9 * t_new / n);
  std::printf("  ratio old/new: %.2f\n", t_old / t_new);
  std::string c;
  const double t_npy = pcsim_bench::seconds_per_call([&] { npy_rows(rows, c); }, 5, 1);
  std::printf("  npy (8 bytes per number, append per row): %.2f ms  %.2f ns/number  (%zu bytes)\n", 1e3 * t_npy,
              1e9 * t_npy / n, c.size());
  std::printf("  ratio new (csv) / npy: %.1f\n", t_new / t_npy);
  const double w_csv = writer_seconds(rows, false, 5), w_npy = writer_seconds(rows, true, 5);
  std::printf("the whole writer (thread, file, fsync), wall, best of 5: csv %.2f ms, npy %.2f ms, ratio %.1f\n",
              1e3 * w_csv, 1e3 * w_npy, w_csv / w_npy);

  std::vector<double> random(200000);
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> lg(-300, 300);
  for (double& x : random) x = std::pow(10.0, lg(rng)) * ((rng() & 1) ? 1 : -1);
  char buf[64];
  volatile std::size_t sink = 0;
  const double r_old = pcsim_bench::seconds_per_call([&] {
    for (double x : random) sink = sink + static_cast<std::size_t>(std::to_chars(buf, buf + 64, x).ptr - buf);
  }, 5, 1);
  const double r_new = pcsim_bench::seconds_per_call([&] {
    for (double x : random) sink = sink + static_cast<std::size_t>(pcsim::write_number(buf, x) - buf);
  }, 5, 1);
  std::printf("numbers log-uniform in 1e-300..1e300, formatter alone:\n");
  std::printf("  std::to_chars %.1f ns, write_number %.1f ns, ratio %.2f\n", 1e9 * r_old / 2e5, 1e9 * r_new / 2e5, r_old / r_new);
  return 0;
}
