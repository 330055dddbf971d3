// The drawing table of a model file ([model.draw], docs/model-files.md "Drawing"): named points
// whose coordinates are expressions of q, q_d, t and the parameters, and the lines, polygons,
// circles and force arrows drawn between them; read and checked with the rest of the file, and
// compiled (with pcsim's own expression parser) into a small evaluator of plain doubles.
#pragma once

#include <filesystem>
#include <map>
#include <memory>
#include <string>
#include <vector>

namespace pcsim::modelfile {

/// One point of a drawing: `[[model.draw.point]]` (named), or a coordinate table written in
/// place inside a line, polygon, circle or arrow (anonymous: `name` is the key it came from).
struct DrawPoint {
  std::string name;
  bool named = true;
  std::string x, y, z;  ///< expressions as written; z "" in a planar drawing
  /// `follows = "P"`: magnified displacements move this point with the earlier named point P,
  /// at its true offset from P (an eccentric mass on its axis, a spoke on its wheel); -1: none.
  int follows = -1;
};

/// One shape of a drawing.
struct DrawShape {
  enum class Kind { line, polygon, circle, arrow } kind = Kind::line;
  std::string key;               ///< "model.draw.line[2]", for messages
  std::vector<int> points;       ///< line, polygon: the vertices; circle: the centre; arrow: the foot
  bool closed = false;           ///< line: back to the first point
  std::string radius;            ///< circle: expression
  std::string color;             ///< "#rrggbb" ("" = the default)
  std::string fill;              ///< polygon, circle: "#rrggbb" ("" = none)
  std::string mode;              ///< colored by this unilateral constraint's contact mode ("" none)
  std::string force;             ///< arrow: the time-series column (R_<coordinate> or an output)
  std::string dx, dy, dz;        ///< arrow: the direction (normalized when drawn)
  double unit = 1.0;             ///< arrow: this many units of `force` ...
  double length = 1.0;           ///< ... are drawn `length` long (drawing units, e.g. m)
  std::string unit_name;         ///< arrow: "N" (default) or as written
};

/// A model's drawing ([model.draw]); empty() when the file has none.
struct DrawSpec {
  bool spatial = false;          ///< `view = "3d"` (points have z)
  double magnify = 1.0;          ///< the initial displacement magnification shown
  std::vector<DrawPoint> points;
  std::vector<DrawShape> shapes;
  bool empty() const { return shapes.empty() && points.empty(); }
};

/// A drawing compiled for evaluation: every point coordinate, radius and arrow direction as a
/// straight-line program over the inputs (t, the time-series columns a drawing may use, and the
/// parameters), evaluated without GiNaC (so from any thread, fast enough for every row of a run).
class DrawEvaluator {
 public:
  /// Reads the model file and compiles its drawing over the inputs input_names(): t, the
  /// coordinates, their velocities <name>_d, then the parameters (file order). Throws
  /// InputError naming the model file and the key for a bad file, or a drawing expression that
  /// does not parse or uses a definition that needs what a drawing has not (accelerations).
  explicit DrawEvaluator(const std::filesystem::path& model_file);
  ~DrawEvaluator();
  DrawEvaluator(DrawEvaluator&&) noexcept;

  const DrawSpec& spec() const;
  const std::string& model_name() const;
  const std::vector<std::string>& coordinates() const;
  const std::vector<std::string>& input_names() const;
  /// The model's parameters with their defaults, in file order.
  const std::vector<std::pair<std::string, double>>& parameter_defaults() const;
  /// The model's excitation period for these inputs (NaN without [model] period).
  double period(const std::vector<double>& inputs) const;

  /// Number of values evaluate() writes: 3 per point (x, y, z; z = 0 when planar), then one
  /// radius per circle and 3 direction components per arrow (in shape order).
  std::size_t size() const;
  void evaluate(const std::vector<double>& inputs, double* out) const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace pcsim::modelfile
