// The software rasterizer and the ffmpeg pipe of `pcsim animate --video` (video.hpp).
#include "animate/video.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <functional>
#include <map>

#include <unistd.h>

#include "common/error.hpp"
#include "common/format.hpp"
#include "common/gnuplot.hpp"

namespace pcsim::animate {

namespace fs = std::filesystem;
using Kind = modelfile::DrawShape::Kind;

namespace {

struct Rgb {
  unsigned char r, g, b;
};

Rgb parse_color(const std::string& hex, Rgb fallback) {
  if (hex.size() != 7) return fallback;
  const unsigned long v = std::strtoul(hex.c_str() + 1, nullptr, 16);
  return {static_cast<unsigned char>(v >> 16), static_cast<unsigned char>(v >> 8), static_cast<unsigned char>(v)};
}

Rgb mode_color(const std::string& m, Rgb fallback) {
  if (m == "stick") return {0x2a, 0x9d, 0x4a};
  if (m == "slip") return {0xe0, 0x7b, 0x00};
  if (m == "flight") return {0xd6, 0x28, 0x28};
  if (m == "contact") return {0x1f, 0x77, 0xb4};
  return fallback;
}

// A 3x5 font for the label: digits, '.', '-', '+', 'e', 't', 's', 'x', '=' and space.
const std::map<char, unsigned> kGlyphs = {
    {'0', 0x7B6F}, {'1', 0x2C97}, {'2', 0x73E7}, {'3', 0x73CF}, {'4', 0x5BC9}, {'5', 0x79CF},
    {'6', 0x79EF}, {'7', 0x7249}, {'8', 0x7BEF}, {'9', 0x7BCF}, {'.', 0x0002}, {'-', 0x01C0},
    {'+', 0x05D0}, {'e', 0x0FE7}, {'t', 0x2E93}, {'s', 0x388E}, {'x', 0x0AA8}, {'=', 0x0E38},
    {' ', 0x0000}};

// A pixel coordinate as an int, clamped first (a magnified point may lie far outside the frame,
// and converting a double beyond int's range is undefined).
int pix(double v) { return static_cast<int>(std::clamp(v, -1e6, 1e6)); }

}  // namespace

Rasterizer::Rasterizer(const Scene& s, int width, int height, double magnify)
    : s_(s), w_(width), h_(height), mag_(magnify), rgb_(static_cast<std::size_t>(width) * height * 3) {
  const std::size_t P = s.spec.points.size();
  for (int k = 0; k < 3; ++k) {
    lo_[k] = INFINITY;
    hi_[k] = -INFINITY;
  }
  for (std::size_t f = 0; f < s.t.size(); ++f) {
    for (std::size_t i = 0; i < P; ++i) {
      const auto p = world(f, i);
      for (int k = 0; k < 3; ++k)
        if (std::isfinite(p[k])) {
          lo_[k] = std::min(lo_[k], p[k]);
          hi_[k] = std::max(hi_[k], p[k]);
        }
    }
    std::size_t vi = 3 * P;
    for (const auto& sh : s.spec.shapes) {
      if (sh.kind == Kind::circle) {
        const double r = std::abs(s.values[f][vi++]);
        const auto c = world(f, static_cast<std::size_t>(sh.points[0]));
        if (std::isfinite(r))
          for (int k = 0; k < 2; ++k) {
            lo_[k] = std::min(lo_[k], c[k] - r);
            hi_[k] = std::max(hi_[k], c[k] + r);
          }
      } else if (sh.kind == Kind::arrow) {
        vi += 3;
      }
    }
  }
  for (int k = 0; k < 3; ++k) {
    if (!std::isfinite(lo_[k])) lo_[k] = -1, hi_[k] = 1;
    c_[k] = (lo_[k] + hi_[k]) / 2;
    r_ = std::max(r_ == 1 && k == 0 ? 1e-12 : r_, (hi_[k] - lo_[k]) / 2);
  }
  if (!s.spatial) {
    const double sx = (w_ - 40) / std::max(1e-300, hi_[0] - lo_[0]), sy = (h_ - 40) / std::max(1e-300, hi_[1] - lo_[1]);
    scale_ = std::min(sx, sy);
    if (!std::isfinite(scale_) || scale_ <= 0) scale_ = 1;
  } else {
    scale_ = 0.45 * std::min(w_, h_) / r_;
  }
}

std::array<double, 3> Rasterizer::world(std::size_t f, std::size_t i) const {
  std::array<double, 3> p{};
  for (int k = 0; k < 3; ++k) {
    const double m = s_.mean[f][3 * i + k];
    p[k] = m + mag_ * (s_.values[f][3 * i + k] - m);
  }
  if (!s_.spatial) p[2] = 0;
  return p;
}

std::array<double, 2> Rasterizer::project(const std::array<double, 3>& p) const {
  if (!s_.spatial) return {w_ / 2.0 + (p[0] - c_[0]) * scale_, h_ / 2.0 - (p[1] - c_[1]) * scale_};
  // The page's camera at its starting angle (az 0.6, el 0.35), z up.
  const double az = 0.6, el = 0.35;
  const double x = p[0] - c_[0], y = p[1] - c_[1], z = p[2] - c_[2];
  const double xr = std::cos(az) * x + std::sin(az) * y, yr = -std::sin(az) * x + std::cos(az) * y;
  const double depth = std::cos(el) * yr + std::sin(el) * z, up = -std::sin(el) * yr + std::cos(el) * z;
  const double dist = 4 * r_, persp = dist / (dist + depth);
  return {w_ / 2.0 + xr * scale_ * persp, h_ / 2.0 - up * scale_ * persp};
}

std::pair<double, double> Rasterizer::pixel(std::size_t f, std::size_t i) const {
  const auto q = project(world(f, i));
  return {q[0], q[1]};
}

const std::vector<unsigned char>& Rasterizer::draw(std::size_t f) {
  std::fill(rgb_.begin(), rgb_.end(), 255);
  auto blend = [&](int x, int y, Rgb c, double a) {
    if (x < 0 || y < 0 || x >= w_ || y >= h_ || !(a > 0)) return;
    a = std::min(1.0, a);
    unsigned char* px = &rgb_[(static_cast<std::size_t>(y) * w_ + x) * 3];
    px[0] = static_cast<unsigned char>(px[0] + (c.r - px[0]) * a);
    px[1] = static_cast<unsigned char>(px[1] + (c.g - px[1]) * a);
    px[2] = static_cast<unsigned char>(px[2] + (c.b - px[2]) * a);
  };
  // Pixels within half the width of a segment (anti-aliased by the distance).
  auto segment = [&](std::array<double, 2> a, std::array<double, 2> b, double width, Rgb c) {
    if (!(std::isfinite(a[0]) && std::isfinite(a[1]) && std::isfinite(b[0]) && std::isfinite(b[1]))) return;
    const double hw = width / 2;
    const int x0 = std::max(0, pix(std::floor(std::min(a[0], b[0]) - hw - 1)));
    const int x1 = std::min(w_ - 1, pix(std::ceil(std::max(a[0], b[0]) + hw + 1)));
    const int y0 = std::max(0, pix(std::floor(std::min(a[1], b[1]) - hw - 1)));
    const int y1 = std::min(h_ - 1, pix(std::ceil(std::max(a[1], b[1]) + hw + 1)));
    const double dx = b[0] - a[0], dy = b[1] - a[1], L2 = dx * dx + dy * dy;
    for (int y = y0; y <= y1; ++y)
      for (int x = x0; x <= x1; ++x) {
        const double px = x + 0.5 - a[0], py = y + 0.5 - a[1];
        const double u = L2 > 0 ? std::clamp((px * dx + py * dy) / L2, 0.0, 1.0) : 0.0;
        const double d = std::hypot(px - u * dx, py - u * dy);
        blend(x, y, c, hw + 0.5 - d);
      }
  };
  auto ring = [&](std::array<double, 2> c, double r, double width, Rgb col, bool fill, Rgb fc) {
    if (!(std::isfinite(c[0]) && std::isfinite(c[1]) && std::isfinite(r))) return;
    const double hw = width / 2;
    const int x0 = std::max(0, pix(c[0] - r - hw - 1)), x1 = std::min(w_ - 1, pix(c[0] + r + hw + 1));
    const int y0 = std::max(0, pix(c[1] - r - hw - 1)), y1 = std::min(h_ - 1, pix(c[1] + r + hw + 1));
    for (int y = y0; y <= y1; ++y)
      for (int x = x0; x <= x1; ++x) {
        const double d = std::hypot(x + 0.5 - c[0], y + 0.5 - c[1]);
        if (fill) blend(x, y, fc, r + 0.5 - d);
        blend(x, y, col, hw + 0.5 - std::abs(d - r));
      }
  };
  auto polygon = [&](const std::vector<std::array<double, 2>>& v, Rgb c) {
    double xl = INFINITY, xh = -INFINITY, yl = INFINITY, yh = -INFINITY;
    for (const auto& p : v) {
      if (!(std::isfinite(p[0]) && std::isfinite(p[1]))) return;
      xl = std::min(xl, p[0]), xh = std::max(xh, p[0]), yl = std::min(yl, p[1]), yh = std::max(yh, p[1]);
    }
    for (int y = std::max(0, pix(yl)); y <= std::min(h_ - 1, pix(yh) + 1); ++y)
      for (int x = std::max(0, pix(xl)); x <= std::min(w_ - 1, pix(xh) + 1); ++x) {
        bool in = false;
        const double px = x + 0.5, py = y + 0.5;
        for (std::size_t i = 0, j = v.size() - 1; i < v.size(); j = i++)
          if ((v[i][1] > py) != (v[j][1] > py) &&
              px < (v[j][0] - v[i][0]) * (py - v[i][1]) / (v[j][1] - v[i][1]) + v[i][0])
            in = !in;
        if (in) blend(x, y, c, 1);
      }
  };
  auto text = [&](int x, int y, const std::string& s, int k) {
    for (char ch : s) {
      const auto it = kGlyphs.find(ch);
      const unsigned g = it == kGlyphs.end() ? 0 : it->second;
      for (int r = 0; r < 5; ++r)
        for (int c = 0; c < 3; ++c)
          if (g >> (14 - (r * 3 + c)) & 1u)
            for (int dy = 0; dy < k; ++dy)
              for (int dx = 0; dx < k; ++dx) blend(x + c * k + dx, y + r * k + dy, {0, 0, 0}, 1);
      x += 4 * k;
    }
  };

  const std::size_t P = s_.spec.points.size();
  std::vector<std::array<double, 3>> wpt(P);
  std::vector<std::array<double, 2>> ppt(P);
  for (std::size_t i = 0; i < P; ++i) {
    wpt[i] = world(f, i);
    ppt[i] = project(wpt[i]);
  }
  std::size_t vi = 3 * P, ai = 0;
  const Rgb ink{0x33, 0x33, 0x33};
  for (const auto& sh : s_.spec.shapes) {
    Rgb col = parse_color(sh.color, ink);
    if (!sh.mode.empty())
      for (std::size_t k = 0; k < s_.contacts.size(); ++k)
        if (s_.contacts[k] == sh.mode && k < s_.modes[f].size()) col = mode_color(s_.modes[f][k], col);
    if (sh.kind == Kind::line || sh.kind == Kind::polygon) {
      std::vector<std::array<double, 2>> v;
      for (int i : sh.points) v.push_back(ppt[static_cast<std::size_t>(i)]);
      if (sh.kind == Kind::polygon && !sh.fill.empty()) polygon(v, parse_color(sh.fill, ink));
      for (std::size_t k = 0; k + 1 < v.size(); ++k) segment(v[k], v[k + 1], 2, col);
      if (sh.kind == Kind::polygon || sh.closed) segment(v.back(), v.front(), 2, col);
    } else if (sh.kind == Kind::circle) {
      const double r = std::abs(s_.values[f][vi++]) * scale_;
      ring(ppt[static_cast<std::size_t>(sh.points[0])], r, 2, col, !sh.fill.empty(), parse_color(sh.fill, ink));
    } else {
      const double dx = s_.values[f][vi], dy = s_.values[f][vi + 1], dz = s_.values[f][vi + 2];
      vi += 3;
      const double force = s_.forces[f][ai++];
      const double n = std::sqrt(dx * dx + dy * dy + dz * dz);
      if (!(n > 0) || !std::isfinite(force)) continue;
      const double len = force / sh.unit * sh.length;
      const auto& a = wpt[static_cast<std::size_t>(sh.points[0])];
      const auto pa = ppt[static_cast<std::size_t>(sh.points[0])];
      const auto pb = project({a[0] + len * dx / n, a[1] + len * dy / n, a[2] + len * dz / n});
      const Rgb ac = parse_color(sh.color, {0xc0, 0x39, 0x2b});
      segment(pa, pb, 2, ac);
      const double ex = pb[0] - pa[0], ey = pb[1] - pa[1], L = std::hypot(ex, ey);
      if (L > 1) {
        const double ux = ex / L, uy = ey / L, h = std::min(10.0, L / 2);
        polygon({pb, {pb[0] - h * ux + 0.5 * h * uy, pb[1] - h * uy - 0.5 * h * ux},
                 {pb[0] - h * ux - 0.5 * h * uy, pb[1] - h * uy + 0.5 * h * ux}}, ac);
      }
    }
  }
  for (std::size_t i = 0; i < P; ++i)
    if (s_.spec.points[i].named) ring(ppt[i], 2, 1, {0, 0, 0}, true, {0, 0, 0});
  char label[96];
  std::snprintf(label, sizeof label, "t=%.3f s  x%s", s_.t[f], format_significant(mag_, 4).c_str());
  text(10, h_ - 25, label, 3);
  return rgb_;
}

void write_video(const Scene& scene, const fs::path& file, const VideoOptions& o) {
  const auto ffmpeg = find_on_path("ffmpeg");
  if (!ffmpeg)
    throw Error("pcsim animate --video needs ffmpeg on PATH (Debian package ffmpeg; "
                "scripts/install-deps.sh installs it)");
  const double t0 = scene.t.front(), t1 = scene.t.back();
  double speed = o.speed;
  const double needed = (t1 - t0) / speed * o.fps;
  if (needed > o.max_frames) speed = (t1 - t0) * o.fps / o.max_frames;  // at most max_frames
  const int frames = std::max(1, pix(std::floor((t1 - t0) / speed * o.fps)) + 1);
  Rasterizer raster(scene, o.width, o.height, o.magnify > 0 ? o.magnify : scene.magnify);
  const bool gif = file.extension() == ".gif";
  const fs::path dir = file.has_parent_path() ? file.parent_path() : fs::path(".");
  const std::string tmp = "." + file.filename().string() + ".tmp" + std::to_string(::getpid()) + "-0";
  std::vector<std::string> args = {"-hide_banner", "-loglevel", "error", "-nostdin", "-f", "rawvideo",
                                   "-pix_fmt", "rgb24", "-s",
                                   std::to_string(o.width) + "x" + std::to_string(o.height), "-r",
                                   std::to_string(o.fps), "-i", "pipe:0", "-an"};
  if (gif) {
    for (const char* a : {"-vf", "split[a][b];[a]palettegen[p];[b][p]paletteuse", "-f", "gif"}) args.push_back(a);
  } else {
    for (const char* a : {"-c:v", "libx264", "-pix_fmt", "yuv420p", "-movflags", "+faststart", "-f", "mp4"})
      args.push_back(a);
  }
  args.push_back("./" + tmp);
  const std::string log = "." + file.filename().string() + ".ffmpeg" + std::to_string(::getpid()) + ".log";
  int status = -1;
  try {
    status = run_program(*ffmpeg, args, dir, [&](const std::function<bool(const char*, std::size_t)>& write) {
      std::size_t f = 0;
      for (int k = 0; k < frames; ++k) {
        const double t = t0 + k * speed / o.fps;
        while (f + 1 < scene.t.size() && std::abs(scene.t[f + 1] - t) <= std::abs(scene.t[f] - t)) ++f;
        const auto& rgb = raster.draw(f);
        if (!write(reinterpret_cast<const char*>(rgb.data()), rgb.size())) return;
      }
    }, log);
  } catch (const std::exception& e) {
    std::error_code ec;
    fs::remove(dir / tmp, ec);
    fs::remove(dir / log, ec);
    throw Error(std::string("pcsim animate --video: ") + e.what());
  }
  std::error_code ec;
  std::string why;
  {
    std::FILE* lf = std::fopen((dir / log).c_str(), "r");
    if (lf) {
      char b[300];
      const std::size_t n = std::fread(b, 1, sizeof b - 1, lf);
      b[n] = 0;
      why = b;
      std::fclose(lf);
    }
    fs::remove(dir / log, ec);
  }
  if (status != 0) {
    fs::remove(dir / tmp, ec);
    std::replace(why.begin(), why.end(), '\n', ' ');
    throw Error("pcsim animate --video: ffmpeg failed (exit " + std::to_string(status) + ")" +
                (why.empty() ? std::string() : ": " + why));
  }
  fs::rename(dir / tmp, file, ec);
  if (ec) {
    fs::remove(dir / tmp, ec);
    throw IoError("cannot write " + file.string() + ": " + ec.message());
  }
}

}  // namespace pcsim::animate
