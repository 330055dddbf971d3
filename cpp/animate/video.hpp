// `pcsim animate --video FILE.mp4|FILE.gif`: the scene's frames drawn by a small software
// rasterizer (lines, circles, polygons, arrows, a time and magnification label) as raw RGB
// frames streamed to Debian's ffmpeg (fork/exec with an argument vector, no shell; common/
// gnuplot.hpp run_program), which encodes them into a temporary file beside FILE that replaces
// FILE only when ffmpeg succeeded.
#pragma once

#include <array>
#include <filesystem>
#include <vector>

#include "animate/scene.hpp"

namespace pcsim::animate {

struct VideoOptions {
  int width = 800, height = 600;
  int fps = 25;
  double speed = 1.0;      ///< seconds of motion per second of video
  double magnify = 0;      ///< 0: the drawing's own (scene.magnify)
  int max_frames = 3000;   ///< the video's frames at most (speed is raised to fit)
};

/// One frame as RGB bytes (width * height * 3), at scene frame `f`, with the bounds of every
/// frame at this magnification (so the view does not move).
class Rasterizer {
 public:
  Rasterizer(const Scene& scene, int width, int height, double magnify);
  const std::vector<unsigned char>& draw(std::size_t f);
  /// The pixel of point i in frame f (as draw() places it; tests compare it with the page's).
  std::pair<double, double> pixel(std::size_t f, std::size_t i) const;

 private:
  struct Impl;
  const Scene& s_;
  int w_, h_;
  double mag_;
  double lo_[3], hi_[3], c_[3], r_ = 1, scale_ = 1;
  std::vector<unsigned char> rgb_;
  std::array<double, 3> world(std::size_t f, std::size_t i) const;
  std::array<double, 2> project(const std::array<double, 3>& p) const;
};

/// Writes the video (checked by the caller: a new file, or pcsim's own in the run directory).
/// Throws pcsim::Error when ffmpeg is missing or fails (nothing is left behind).
void write_video(const Scene& scene, const std::filesystem::path& file, const VideoOptions& options);

}  // namespace pcsim::animate
