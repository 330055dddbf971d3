// The frames of an animation: a run directory's own output (summary.json or steady.json, the
// time series, events.csv, and model.toml, the model it ran) read and checked, and the model's
// [model.draw] table evaluated at every row, decimated to the frames a screen needs.
#pragma once

#include <filesystem>
#include <string>
#include <vector>

#include "modelfile/draw.hpp"

namespace pcsim::animate {

struct Event {
  double t = 0;
  std::string kind, constraint, mode_after;
};

/// One mode of a `pcsim modes` directory: its frames are one cycle of the shape.
struct ModePage {
  std::string label;            ///< "mode 2 (oscillatory)"
  std::string text;             ///< its eigenvalue, frequencies, damping, dominant coordinates
  std::size_t first = 0, count = 0;  ///< its frames
  double amplitude = 0;         ///< a in q = q_ref + a Re(v e^{i phi})
  std::string amplitude_text;   ///< how a was chosen, shown on screen
};

struct Scene {
  std::string title;            ///< the case's name
  std::string model;            ///< the model's name
  bool spatial = false;         ///< 3-D drawing
  bool steady = false;          ///< one period of a periodic orbit (`pcsim steady`): looped
  double magnify = 1;           ///< the initial displacement magnification
  double mean_window = 0;       ///< the moving mean's window (s): the excitation period, or 0 = the whole run
  modelfile::DrawSpec spec;
  std::vector<double> t;        ///< the frames' times
  std::vector<std::size_t> row; ///< the time-series row of each frame
  /// Per frame: 3 per point (x, y, z), one radius per circle, 3 per arrow (its direction).
  std::vector<std::vector<double>> values;
  /// Per frame: the moving mean of every point's x, y, z (3 per point).
  std::vector<std::vector<double>> mean;
  /// Per frame: the value of each arrow's force column (in shape order, arrows only).
  std::vector<std::vector<double>> forces;
  std::vector<std::string> contacts;           ///< the switched contacts (mode_<name> columns)
  std::vector<std::vector<std::string>> modes; ///< per frame, per contact
  std::vector<Event> events;
  std::size_t rows = 0;         ///< rows of the time series
  std::string model_file;       ///< where the model came from (model.toml's first line)
  /// A `pcsim modes` directory: per mode its cycle; t of a frame is then the phase phi (rad),
  /// and mean the drawing at the reference state.
  std::vector<ModePage> mode_pages;
};

/// Reads the run directory `dir` and evaluates its drawing at no more than `max_frames` frames
/// (every k-th row, the last row, and the rows at the events). Throws pcsim::InputError (exit
/// 2): not a directory, not a run (no summary.json / steady.json), a half-written or failed run
/// ("complete" not true, a torn time series), no model.toml, a model with nothing to draw (the
/// message names the model file to add [model.draw] to), a bad drawing expression.
Scene read_scene(const std::filesystem::path& dir, int max_frames);

/// Reads a `pcsim modes` directory (modes.json, model.toml): per mode, frames of one cycle of
/// q(phi) = q_ref + a Re(v e^{i phi}), v the mode shape over the coordinates (a real or zero
/// mode: the standing oscillation v cos phi), a chosen so that the largest displacement of a
/// drawn point is 15% of the drawing's size at the reference. Bad input: InputError (exit 2).
Scene read_modes_scene(const std::filesystem::path& dir, int max_frames);

}  // namespace pcsim::animate
