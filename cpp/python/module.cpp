// The `pcsim` Python module (pybind11): the case layer and the applications as a library, with
// the command line's contracts. A case is loaded (sim::load_case, overrides exactly as --set
// gives them), run (sim::run_case), solved for its steady state (steady::steady_case), traced
// along a key (steady::response_case) or swept over a grid (study::sweep_row, the sweep's own
// per-point function); the results come back as the typed result's summary.json (to_json,
// converted generically, so every field the engine adds reaches Python) and the time series as
// a NumPy array over the run's own buffer (no element-by-element copy). The long calls release
// the GIL: nothing in them touches a Python object (the Python arguments are converted to C++
// before, the results to Python after). The errors are the CLI's, as Python exceptions
// (pcsim.InputError, pcsim.NumericalError, pcsim.IoError, defined in __init__.py).
#include <pybind11/complex.h>
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <algorithm>
#include <cmath>
#include <complex>
#include <cstdio>
#include <cstring>
#include <exception>
#include <filesystem>
#include <memory>
#include <optional>
#include <string>
#include <tuple>
#include <utility>
#include <vector>

#include <nlohmann/json.hpp>

#include "common/error.hpp"
#include "common/format.hpp"
#include "common/location.hpp"
#include "common/parallel.hpp"
#include "common/version.hpp"
#include "mech/contacts/switching.hpp"
#include "mech/dynamics.hpp"
#include "sim/case.hpp"
#include "sim/check.hpp"
#include "sim/client.hpp"
#include "sim/result.hpp"
#include "sim/run.hpp"
#include "sim/vary.hpp"
#include "modes/modes_case.hpp"
#include "steady/response.hpp"
#include "steady/steady_case.hpp"
#include "study/sweep.hpp"
#include "study/table.hpp"
#if PCSIM_WITH_SIEVE
#include "sieve/source.hpp"
#endif

namespace py = pybind11;
namespace fs = std::filesystem;
using namespace pcsim;

namespace {

// ---- JSON and arrays ------------------------------------------------------------------------

/// Any JSON value as the Python value json.loads gives for its text (dict, list, str, int,
/// float, bool, None), so every field of summary.json reaches Python without a list of names.
py::object to_python(const nlohmann::json& j) {
  switch (j.type()) {
    case nlohmann::json::value_t::null: return py::none();
    case nlohmann::json::value_t::boolean: return py::bool_(j.get<bool>());
    case nlohmann::json::value_t::number_integer: return py::int_(j.get<std::int64_t>());
    case nlohmann::json::value_t::number_unsigned: return py::int_(j.get<std::uint64_t>());
    case nlohmann::json::value_t::number_float: return py::float_(j.get<double>());
    case nlohmann::json::value_t::string: return py::str(j.get_ref<const std::string&>());
    case nlohmann::json::value_t::array: {
      py::list l;
      for (const auto& e : j) l.append(to_python(e));
      return std::move(l);
    }
    case nlohmann::json::value_t::object: {
      py::dict d;
      for (const auto& [k, v] : j.items()) d[py::str(k)] = to_python(v);
      return std::move(d);
    }
    default: return py::none();
  }
}

/// A rows x cols array over `values` (moved to the heap, owned by a capsule): no copy.
py::array_t<double> owned_matrix(std::vector<double>&& values, py::ssize_t cols) {
  auto* heap = new std::vector<double>(std::move(values));
  py::capsule owner(heap, [](void* p) { delete static_cast<std::vector<double>*>(p); });
  const py::ssize_t rows = cols > 0 ? static_cast<py::ssize_t>(heap->size()) / cols : 0;
  return py::array_t<double>({rows, cols},
                             {cols * static_cast<py::ssize_t>(sizeof(double)),
                              static_cast<py::ssize_t>(sizeof(double))},
                             heap->data(), owner);
}

/// An Eigen matrix or vector as a NumPy array: one memcpy of the contiguous block (a matrix
/// in Eigen's column-major order, so a Fortran-ordered array).
py::array to_array(const Eigen::MatrixXd& m) {
  py::array_t<double, py::array::f_style> a(
      {static_cast<py::ssize_t>(m.rows()), static_cast<py::ssize_t>(m.cols())});
  if (m.size()) std::memcpy(a.mutable_data(), m.data(), sizeof(double) * static_cast<std::size_t>(m.size()));
  return std::move(a);
}
py::array_t<double> to_array(const Eigen::VectorXd& v) {
  py::array_t<double> a(static_cast<py::ssize_t>(v.size()));
  if (v.size()) std::memcpy(a.mutable_data(), v.data(), sizeof(double) * static_cast<std::size_t>(v.size()));
  return a;
}

// ---- errors -----------------------------------------------------------------------------------

py::object pcsim_attr(const char* name) { return py::module_::import("pcsim").attr(name); }

/// Raises the Python exception `type(args...)` (the GIL held) and leaves to pybind11.
[[noreturn]] void raise(py::object instance) {
  PyErr_SetObject(reinterpret_cast<PyObject*>(Py_TYPE(instance.ptr())), instance.ptr());
  throw py::error_already_set();
}

/// The file and key an InputError's message names ("FILE: key 'KEY': ..."), or None.
std::pair<py::object, py::object> file_and_key(const std::string& msg) {
  py::object file = py::none(), key = py::none();
  const std::string marker = ": key '";
  const std::size_t at = msg.find(marker);
  if (at != std::string::npos) {
    file = py::str(msg.substr(0, at));
    const std::size_t b = at + marker.size(), e = msg.find('\'', b);
    if (e != std::string::npos) key = py::str(msg.substr(b, e - b));
  } else if (const std::size_t c = msg.find(": "); c != std::string::npos) {
    const std::string head = msg.substr(0, c);
    if (head.size() > 5 && head.compare(head.size() - 5, 5, ".toml") == 0) file = py::str(head);
  }
  return {file, key};
}

[[noreturn]] void raise_input(const std::string& msg, py::object file = py::none(),
                              py::object key = py::none()) {
  if (file.is_none() && key.is_none()) std::tie(file, key) = file_and_key(msg);
  raise(pcsim_attr("InputError")(msg, py::arg("file") = file, py::arg("key") = key));
}

class PyRun;
[[noreturn]] void raise_numerical(const NumericalError& e, py::object result) {
  raise(pcsim_attr("NumericalError")(std::string(e.what()), py::arg("time") = e.time(),
                                     py::arg("result") = result));
}

/// Runs `f` with the GIL released; an exception of f is rethrown with the GIL held.
template <class F> void without_gil(F&& f) {
  std::exception_ptr error;
  {
    py::gil_scoped_release nogil;
    try {
      f();
    } catch (...) {
      error = std::current_exception();
    }
  }
  if (error) std::rethrow_exception(error);
}

// ---- arguments --------------------------------------------------------------------------------

std::string text_of_path(const py::handle& p, const char* argument) {
  if (py::isinstance<py::str>(p)) return p.cast<std::string>();
  py::object os = py::module_::import("os");
  if (py::hasattr(p, "__fspath__")) return py::str(os.attr("fspath")(p)).cast<std::string>();
  throw py::type_error(std::string(argument) + ": expected a path (str or os.PathLike), got " +
                       py::str(py::type::of(p).attr("__name__")).cast<std::string>());
}

std::string type_name(const py::handle& v) {
  return py::str(py::type::of(v).attr("__name__")).cast<std::string>();
}

/// One override's value as the text --set would carry: strings as given, booleans as
/// true/false, integers in decimal, floats as the shortest text that reads back to the same
/// double. A non-finite float is refused naming the key (`where`: the case file).
std::string override_text(const std::string& key, const py::handle& v, const std::string& where) {
  if (py::isinstance<py::bool_>(v)) return v.cast<bool>() ? "true" : "false";
  if (py::isinstance<py::int_>(v)) return py::str(v).cast<std::string>();
  if (py::isinstance<py::float_>(v)) {
    const double x = v.cast<double>();
    if (!std::isfinite(x))
      raise_input(where + ": key '" + key + "': expected a finite number, got " + format_number(x),
                  py::str(where), py::str(key));
    return format_number(x);
  }
  if (py::isinstance<py::str>(v)) return v.cast<std::string>();
  throw py::type_error("set['" + key + "']: expected a number, a bool or a str, got " +
                       type_name(v));
}

/// The overrides of `set` (dict: dotted key -> value) and `constraints` (dict: name -> bool to
/// switch an offered constraint on or off, or str to add a holonomic constraint NAME = EXPR,
/// as --constraint does), in that order: the command line's order of --set, then --constraint.
std::vector<sim::Override> overrides_of(const py::object& set, const py::object& constraints,
                                        const std::string& where) {
  std::vector<sim::Override> out;
  if (!set.is_none()) {
    if (!py::isinstance<py::dict>(set))
      throw py::type_error("set: expected a dict of dotted case keys to values, e.g. "
                           "{'parameters.omega': 300}, got " + type_name(set));
    for (const auto& [k, v] : set.cast<py::dict>()) {
      if (!py::isinstance<py::str>(k))
        throw py::type_error("set: keys must be str (dotted case keys), got " + type_name(k));
      const std::string key = k.cast<std::string>();
      out.emplace_back(key, override_text(key, v, where));
    }
  }
  if (!constraints.is_none()) {
    if (!py::isinstance<py::dict>(constraints))
      throw py::type_error("constraints: expected a dict of constraint names to True/False "
                           "(switch an offered constraint) or str (add NAME = EXPR), got " +
                           type_name(constraints));
    std::vector<std::string> added;
    for (const auto& [k, v] : constraints.cast<py::dict>()) {
      if (!py::isinstance<py::str>(k))
        throw py::type_error("constraints: keys must be str (constraint names), got " + type_name(k));
      const std::string name = k.cast<std::string>();
      if (py::isinstance<py::bool_>(v))
        out.emplace_back("constraints." + name, v.cast<bool>() ? "true" : "false");
      else if (py::isinstance<py::str>(v))
        added.push_back(name + "=" + v.cast<std::string>());
      else
        throw py::type_error("constraints['" + name + "']: expected True/False or an expression "
                             "str, got " + type_name(v));
    }
    for (auto& o : sim::command_line_overrides({}, added)) out.push_back(std::move(o));
  }
  return out;
}

std::vector<std::string> string_list(const py::object& v, const char* argument) {
  if (py::isinstance<py::str>(v)) return {v.cast<std::string>()};
  std::vector<std::string> out;
  if (!py::isinstance<py::sequence>(v))
    throw py::type_error(std::string(argument) + ": expected a str or a list of str, got " + type_name(v));
  for (const auto& e : v.cast<py::sequence>()) {
    if (!py::isinstance<py::str>(e))
      throw py::type_error(std::string(argument) + ": expected str items, got " + type_name(e));
    out.push_back(e.cast<std::string>());
  }
  return out;
}

std::optional<fs::path> out_path(const py::object& out) {
  if (out.is_none()) return std::nullopt;
  return fs::path(text_of_path(out, "out"));
}

OdeMethod method_of(const std::string& m) {
  const auto method = parse_ode_method(m);
  if (!method) raise_input("method: expected radau, explicit or auto, got '" + m + "'");
  return *method;
}

/// A state vector argument: a sequence of n finite floats, else ValueError/TypeError naming it.
Eigen::VectorXd state(const py::object& v, int n, const char* argument,
                      const std::vector<std::string>& names) {
  py::array_t<double, py::array::c_style | py::array::forcecast> a;
  try {
    a = py::array_t<double, py::array::c_style | py::array::forcecast>::ensure(v);
  } catch (const py::error_already_set&) {
    a = {};
  }
  if (!a || a.ndim() != 1) {
    std::string list;
    for (const auto& s : names) list += (list.empty() ? "" : ", ") + s;
    throw py::type_error(std::string(argument) + ": expected a 1-D sequence of " +
                         std::to_string(n) + " numbers (" + list + "), got " + type_name(v));
  }
  if (a.shape(0) != n) {
    std::string list;
    for (const auto& s : names) list += (list.empty() ? "" : ", ") + s;
    throw py::value_error(std::string(argument) + ": expected " + std::to_string(n) +
                          " values (" + list + "), got " + std::to_string(a.shape(0)));
  }
  Eigen::VectorXd x(n);
  for (int i = 0; i < n; ++i) {
    x[i] = a.at(i);
    if (!std::isfinite(x[i]))
      throw py::value_error(std::string(argument) + "[" + std::to_string(i) + "] (" + names[i] +
                            "): expected a finite number, got " + format_number(x[i]));
  }
  return x;
}

// ---- results ------------------------------------------------------------------------------------

/// A table of numbers with named columns: a 2-D array and access by name.
struct Table {
  std::vector<std::string> columns;
  py::array_t<double> data;

  py::ssize_t index(const std::string& name) const {
    for (std::size_t j = 0; j < columns.size(); ++j)
      if (columns[j] == name) return static_cast<py::ssize_t>(j);
    std::string known;
    for (std::size_t j = 0; j < columns.size() && j < 40; ++j) known += (j ? ", " : "") + columns[j];
    throw py::key_error("no column '" + name + "' (the columns: " + known +
                        (columns.size() > 40 ? ", ..." : "") + ")");
  }
  /// The column's view (no copy).
  py::object column(const std::string& name) const {
    const py::ssize_t j = index(name);
    return data[py::make_tuple(py::slice(py::none(), py::none(), py::none()), j)];
  }
};

/// One run's result (run_case): summary.json as a dict, the time series, the events.
class PyRun : public Table {
 public:
  py::dict summary;
  py::object events = py::none();  ///< dict column -> array, with contact.switching
  std::string report;
  bool complete = false;
  std::vector<std::string> mode_labels;
};

/// The CLI's events.csv as columns: numbers as float arrays, text as str lists.
py::object events_of(const std::string& csv) {
  if (csv.empty()) return py::none();
  std::vector<std::string> lines;
  std::size_t b = 0;
  while (b < csv.size()) {
    std::size_t e = csv.find('\n', b);
    if (e == std::string::npos) e = csv.size();
    lines.push_back(csv.substr(b, e - b));
    b = e + 1;
  }
  if (lines.empty()) return py::none();
  const auto header = study::parse_csv_line(lines[0]);
  if (!header) return py::none();
  std::vector<std::vector<std::string>> rows;
  for (std::size_t i = 1; i < lines.size(); ++i)
    if (auto r = study::parse_csv_line(lines[i]); r && r->size() == header->size()) rows.push_back(*r);
  py::dict out;
  for (std::size_t j = 0; j < header->size(); ++j) {
    bool numeric = true;
    std::vector<double> v;
    for (const auto& r : rows) {
      const std::string& f = r[j];
      if (f.empty()) { v.push_back(NAN); continue; }
      char* end = nullptr;
      const double x = std::strtod(f.c_str(), &end);
      if (end != f.c_str() + f.size()) { numeric = false; break; }
      v.push_back(x);
    }
    if (numeric) {
      py::array_t<double> a(static_cast<py::ssize_t>(v.size()));
      if (!v.empty()) std::memcpy(a.mutable_data(), v.data(), v.size() * sizeof(double));
      out[py::str((*header)[j])] = a;
    } else {
      py::list l;
      for (const auto& r : rows) l.append(py::str(r[j]));
      out[py::str((*header)[j])] = py::array(l);
    }
  }
  return std::move(out);
}

py::object make_run(const sim::Case& c, const sim::RunResult& r, sim::Kept&& kept,
                    std::string report) {
  auto run = std::make_unique<PyRun>();
  run->columns = r.columns;
  run->data = owned_matrix(std::move(kept.rows), static_cast<py::ssize_t>(r.columns.size()));
  nlohmann::json j = sim::to_json(r);
  run->summary = to_python(j).cast<py::dict>();
  run->events = events_of(kept.events_csv);
  run->report = std::move(report);
  run->complete = r.complete;
  if (!sim::switched_contacts(c).empty())
    for (auto m : {mech::ContactMode::flight, mech::ContactMode::contact, mech::ContactMode::stick,
                   mech::ContactMode::slip})
      run->mode_labels.push_back(mech::to_string(m));
  return py::cast(std::move(run));
}

/// pcsim steady's result: steady.json as a dict.
struct PySteady {
  py::dict data;
  std::string report;
};

/// pcsim modes' result: modes.json (or, with vary, modes_vary.json) as a dict, and its
/// eigenvalues and mode shapes as complex arrays.
struct PyModes {
  py::dict data;
  std::string report;
  py::object eigenvalues, mode_eigenvalues, shapes, values;
  std::vector<std::string> coordinates;
  bool vary = false;
};

/// pcsim response's result: response.csv as a table (numbers; text fields as NaN, the text in
/// `text`), response.json as a dict.
struct PyResponse : Table {
  py::dict meta;
  std::vector<std::vector<std::string>> text;
  py::list summaries;
};

/// A sweep's result: sweep.csv's table (numbers, booleans 1/0, empty fields NaN), the status
/// and error of each point, and each point's summary.json (None where it failed).
struct PySweep : Table {
  std::vector<std::string> status, errors;
  py::list summaries;
};

/// pcsim check's result (sim::check_case): the typed report and the text the CLI prints.
struct PyCheck {
  sim::CheckReport r;
  std::string report;
};

double field_number(const std::string& f) {
  if (f == "true") return 1.0;
  if (f == "false") return 0.0;
  if (f.empty()) return NAN;
  char* end = nullptr;
  const double x = std::strtod(f.c_str(), &end);
  return end == f.c_str() + f.size() ? x : NAN;
}

// ---- the model ------------------------------------------------------------------------------

/// A case's model: its declaration (coordinates, parameters, constraints, outputs) and, at the
/// case's parameter values and active constraints, the engine's quantities at a state.
class PyModel {
 public:
  explicit PyModel(std::shared_ptr<const sim::Case> c) : case_(std::move(c)) {
    const sim::Setup& s = case_->setup;
    model_ = case_->model->instantiate(s.parameters, s.q0, 0.0, case_->table, "");
    std::vector<int> rows;
    for (const auto& name : s.active) rows.push_back(model_->constraint_index(name));
    active_ = std::make_shared<mech::ActiveSet>(mech::ActiveSet::of(*model_, rows));
  }
  const sim::ModelSource& source() const { return *case_->model; }
  std::string name() const { return source().name(); }
  std::vector<std::string> coordinates() const { return source().coordinates(); }
  std::vector<std::string> outputs() const { return source().outputs(); }
  std::vector<std::string> active() const { return case_->setup.active; }
  double period() const { return case_->setup.period; }

  py::dict parameters() const {
    py::dict d;
    for (const auto& p : source().parameters()) {
      py::dict e;
      e["default"] = p.value;
      e["value"] = case_->setup.parameters.at(p.name);
      e["unit"] = p.unit;
      e["meaning"] = p.meaning;
      e["min"] = p.min;
      e["max"] = p.max;
      e["min_exclusive"] = p.min_exclusive;
      e["max_exclusive"] = p.max_exclusive;
      d[py::str(p.name)] = e;
    }
    return d;
  }

  py::list constraints() const {
    py::list l;
    const auto& active = case_->setup.active;
    for (const auto& c : source().constraints()) {
      py::dict e;
      e["name"] = c.name;
      e["kind"] = c.kind == mech::ConstraintKind::holonomic ? "holonomic" : "velocity";
      e["active"] = std::find(active.begin(), active.end(), c.name) != active.end();
      e["active_by_default"] = c.active_by_default;
      e["unilateral"] = c.unilateral;
      e["friction_of"] = c.friction_of;
      e["rough"] = c.rough;
      e["meaning"] = c.meaning;
      l.append(e);
    }
    return l;
  }

  py::dict evaluate(const py::object& q_, const py::object& qd_, const py::object& t_) const {
    const int n = model_->n();
    const auto& names = model_->coordinates();
    std::vector<std::string> dnames;
    for (const auto& s : names) dnames.push_back(s + "_d");
    const Eigen::VectorXd q = state(q_, n, "q", names);
    const Eigen::VectorXd qd = qd_.is_none() ? Eigen::VectorXd::Zero(n) : state(qd_, n, "qd", dnames);
    if (!py::isinstance<py::float_>(t_) && !py::isinstance<py::int_>(t_))
      throw py::type_error("t: expected a number, got " + type_name(t_));
    const double t = t_.cast<double>();
    if (!std::isfinite(t)) throw py::value_error("t: expected a finite number, got " + format_number(t));
    const sim::Setup& s = case_->setup;
    mech::Dynamics dyn(*model_, s.kernel);
    const mech::SimulationOptions so = sim::simulation_options(s);
    mech::ModelIssue issue = dyn.evaluate(*active_, t, q, qd);
    py::dict out;
    out["M"] = to_array(dyn.M);
    out["h"] = to_array(dyn.h);
    out["Q"] = to_array(dyn.Q);
    out["g"] = to_array(dyn.g);
    out["g0"] = to_array(dyn.g0);
    out["gamma"] = to_array(dyn.gamma);
    if (issue == mech::ModelIssue::none) issue = dyn.solve(so.reaction_method);
    if (issue != mech::ModelIssue::none)
      raise(pcsim_attr("NumericalError")("the model cannot be evaluated at this state (" +
                                         std::string(mech::to_string(issue)) + "): " + dyn.message(),
                                         py::arg("time") = t, py::arg("result") = py::none()));
    out["R"] = to_array(dyn.R);
    out["qdd"] = to_array(dyn.qdd);
    out["lambda"] = to_array(dyn.lambda);
    Eigen::VectorXd d(static_cast<Eigen::Index>(model_->derived_names().size()));
    model_->derived(t, q, qd, dyn.qdd, dyn.R, d);
    py::dict outputs;
    for (std::size_t k = 0; k < model_->derived_names().size(); ++k)
      outputs[py::str(model_->derived_names()[k])] = d[static_cast<Eigen::Index>(k)];
    out["outputs"] = outputs;
    return out;
  }

 private:
  std::shared_ptr<const sim::Case> case_;
  std::shared_ptr<const mech::Model> model_;
  std::shared_ptr<mech::ActiveSet> active_;
};

// ---- the case -----------------------------------------------------------------------------------

class PyCase {
 public:
  explicit PyCase(sim::Case c) : case_(std::make_shared<const sim::Case>(std::move(c))) {}

  static PyCase load(const py::object& path, const py::object& set, const py::object& constraints) {
    const std::string file = text_of_path(path, "path");
    std::vector<sim::Override> overrides = overrides_of(set, constraints, file);
    sim::Case c;
    without_gil([&] { c = sim::load_case(file, overrides); });
    return PyCase(std::move(c));
  }

  PyCase with_set(const py::object& set, const py::object& constraints) const {
    const std::vector<sim::Override> overrides =
        overrides_of(set, constraints, input_location(case_->source));
    sim::Case c;
    without_gil([&] { c = sim::case_from_table(case_->table, case_->source, overrides); });
    return PyCase(std::move(c));
  }

  const sim::Case& get() const { return *case_; }
  std::shared_ptr<const sim::Case> shared() const { return case_; }

  py::object run(const py::object& out) const {
    sim::RunOptions options;
    options.out_dir = out_path(out);
    sim::Kept kept;
    options.keep = &kept;
    sim::RunResult r;
    std::string report;
    bool failed = false, unreliable = false;
    std::string message;
    double time = 0;
    std::exception_ptr other;
    {
      py::gil_scoped_release nogil;  // nothing below touches a Python object
      try {
        r = sim::run_case(*case_, options);
        report = sim::human_report(*case_, r);
      } catch (const sim::UnreliableResult& e) {
        r = e.result();
        report = sim::human_report(*case_, r);
        unreliable = failed = true;
        message = e.what();
        time = e.time();
      } catch (const NumericalError& e) {
        failed = true;
        message = e.what();
        time = e.time();
        if (kept.partial) {
          r = *kept.partial;
          report = sim::human_report(*case_, r);
        }
      } catch (...) {
        other = std::current_exception();
      }
    }
    if (other) std::rethrow_exception(other);
    if (!failed) return make_run(*case_, r, std::move(kept), std::move(report));
    py::object partial = (unreliable || kept.partial)
                             ? make_run(*case_, r, std::move(kept), std::move(report))
                             : py::none();
    raise_numerical(NumericalError(message, time), partial);
  }

  PySteady steady(int periods, const std::string& method, int max_iterations,
                  int transient_periods, const py::object& out) const {
    if (periods < 1) raise_input("periods: expected an integer >= 1, got " + std::to_string(periods));
    if (max_iterations < 1) raise_input("max_iterations: expected an integer >= 1");
    if (transient_periods < 0) raise_input("transient_periods: expected an integer >= 0");
    steady::SteadyOptions o;
    o.periods = periods;
    o.method = method_of(method);
    o.max_iterations = max_iterations;
    o.max_transient_periods = transient_periods;
    o.out_dir = out_path(out);
    nlohmann::json s;
    std::string report;
    without_gil([&] {
      s = steady::steady_case(*case_, o);
      report = steady::steady_report(*case_, s);
    });
    PySteady r;
    r.data = to_python(s).cast<py::dict>();
    r.report = std::move(report);
    return r;
  }

  PyModes modes(const py::object& excitation, const py::object& cyclic, const py::object& vary,
              const py::object& out) const {
    // The options as pcsim modes' command line gives them (--excitation, --cyclic / --no-cyclic,
    // --vary, --out): the same functions of cpp/modes compute and write them.
    modes::ModesOptions o;
    if (!excitation.is_none()) {
      if (py::isinstance<py::bool_>(excitation) ||
          !(py::isinstance<py::str>(excitation) || py::isinstance<py::int_>(excitation) || py::isinstance<py::float_>(excitation)))
        throw py::type_error("excitation: expected \"off\" or a phase in rad (a float), got " + type_name(excitation));
      if (py::isinstance<py::str>(excitation)) {
        o.excitation = excitation.cast<std::string>();
      } else {
        const double phase = excitation.cast<double>();
        if (!std::isfinite(phase)) raise_input("excitation: expected a finite phase in rad, got " + format_number(phase));
        char b[40];
        std::snprintf(b, sizeof b, "%.17g", phase);  // the double itself, as --excitation text
        o.excitation = std::string(b);
      }
      if (o.excitation->empty()) raise_input("excitation: expected \"off\" or a phase in rad, got \"\"");
    }
    if (!cyclic.is_none()) o.cyclic = string_list(cyclic, "cyclic");  // [] = --no-cyclic
    std::optional<modes::VarySpec> spec;
    if (!vary.is_none()) {
      if (!py::isinstance<py::str>(vary))
        throw py::type_error("vary: expected a str 'KEY=START:STOP:COUNT', got " + type_name(vary));
      spec = modes::parse_vary(vary.cast<std::string>());
    }
    o.out_dir = out_path(out);
    nlohmann::json j;
    std::string report;
    without_gil([&] {
      if (spec) {
        j = modes::modes_vary(*case_, o, *spec);
        report = modes::vary_report(j);
      } else {
        j = modes::modes_case(*case_, o);
        report = modes::modes_report(*case_, j);
      }
    });
    PyModes r;
    r.vary = static_cast<bool>(spec);
    r.data = to_python(j).cast<py::dict>();
    r.report = std::move(report);
    using cplx = std::complex<double>;
    if (spec) {
      // eigenvalues[step, track], the tracks paired by continuity; values the key's values.
      const auto& tracks = j.at("tracks");
      const auto& vals = j.at("values");
      const py::ssize_t steps = static_cast<py::ssize_t>(vals.size()), nt = static_cast<py::ssize_t>(tracks.size());
      py::array_t<cplx> ev({steps, nt});
      auto e = ev.mutable_unchecked<2>();
      for (py::ssize_t t = 0; t < nt; ++t)
        for (py::ssize_t k = 0; k < steps; ++k) {
          const auto& re = tracks[static_cast<std::size_t>(t)]["re"][static_cast<std::size_t>(k)];
          const auto& im = tracks[static_cast<std::size_t>(t)]["im"][static_cast<std::size_t>(k)];
          e(k, t) = cplx(re.is_number() ? re.get<double>() : NAN, im.is_number() ? im.get<double>() : NAN);
        }
      py::array_t<double> v(steps);
      auto vv = v.mutable_unchecked<1>();
      for (py::ssize_t k = 0; k < steps; ++k) vv(k) = vals[static_cast<std::size_t>(k)].get<double>();
      r.eigenvalues = ev;
      r.values = v;
      r.mode_eigenvalues = py::none();
      r.shapes = py::none();
      return r;
    }
    r.coordinates = j.at("coordinates").get<std::vector<std::string>>();
    const auto& all = j.at("eigenvalues");
    py::array_t<cplx> ev(static_cast<py::ssize_t>(all.size()));
    auto e = ev.mutable_unchecked<1>();
    for (std::size_t k = 0; k < all.size(); ++k)
      e(static_cast<py::ssize_t>(k)) = cplx(all[k]["re"].get<double>(), all[k]["im"].get<double>());
    const auto& ms = j.at("modes");
    const py::ssize_t nm = static_cast<py::ssize_t>(ms.size()), nc = static_cast<py::ssize_t>(r.coordinates.size());
    py::array_t<cplx> lam(nm);
    py::array_t<cplx> shapes({nm, nc});
    auto l = lam.mutable_unchecked<1>();
    auto sh = shapes.mutable_unchecked<2>();
    for (py::ssize_t k = 0; k < nm; ++k) {
      const auto& m = ms[static_cast<std::size_t>(k)];
      l(k) = cplx(m["re"].get<double>(), m["im"].get<double>());
      for (py::ssize_t i = 0; i < nc; ++i) {
        const auto& c = m["shape"][r.coordinates[static_cast<std::size_t>(i)]];
        sh(k, i) = cplx(c["re"].get<double>(), c["im"].get<double>());
      }
    }
    r.eigenvalues = ev;
    r.mode_eigenvalues = lam;
    r.shapes = shapes;
    r.values = py::none();
    return r;
  }

  PyResponse response(const std::string& vary, int periods, const std::string& method,
                      unsigned jobs, bool summaries, const py::object& out) const {
    if (periods < 1) raise_input("periods: expected an integer >= 1, got " + std::to_string(periods));
    steady::ResponseOptions o;
    o.vary = vary;
    o.periods = periods;
    o.method = method_of(method);
    o.jobs = jobs;
    o.summaries = summaries;
    o.out_dir = out_path(out);
    steady::ResponseResult res;
    std::vector<double> values;
    without_gil([&] {
      res = steady::response_case(*case_, o);
      for (const auto& row : res.rows)
        for (std::size_t j = 0; j < res.columns.size(); ++j)
          values.push_back(j < row.size() ? field_number(row[j]) : NAN);
    });
    PyResponse r;
    r.columns = res.columns;
    r.data = owned_matrix(std::move(values), static_cast<py::ssize_t>(res.columns.size()));
    r.meta = to_python(res.meta).cast<py::dict>();
    r.text = res.rows;
    for (const auto& p : res.points)
      r.summaries.append(p.summary ? to_python(sim::to_json(*p.summary)) : py::none());
    return r;
  }

  /// pcsim check: the report at the initial state; a case that cannot run raises InputError
  /// with the message the CLI exits 2 with (its report up to the refusal in .check_report).
  PyCheck check() const {
    PyCheck out;
    without_gil([&] {
      out.r = sim::check_case(*case_);
      out.report = sim::format_check(out.r);
    });
    if (!out.r.can_run) {
      const std::string msg = sim::check_refusal(out.r);
      py::object e = pcsim_attr("InputError")(msg, py::arg("file") = py::none(), py::arg("key") = py::none());
      e.attr("check_report") = py::str(out.report);
      raise(e);
    }
    return out;
  }

  PySweep sweep(const py::object& vary_, unsigned jobs) const {
    const std::vector<std::string> vary = string_list(vary_, "vary");
    if (vary.empty()) raise_input("vary: expected at least one KEY=START:STOP:COUNT or KEY=v1,v2,...");
    std::vector<std::string> header;
    std::vector<std::vector<std::string>> rows;
    std::vector<std::optional<nlohmann::json>> results;
    without_gil([&] {
      const sim::Grid grid = sim::make_grid(vary, *case_);
      header = study::sweep_header(*case_, grid);
      rows.resize(grid.size());
      results.resize(grid.size());
      const study::Runner runner = study::case_runner();
      // Each point as `pcsim sweep` computes its row (study::sweep_row), keeping its summary.
      parallel_for(grid.size(), jobs, [&](std::size_t i) {
        rows[i] = study::sweep_row(*case_, grid, i, [&](const sim::Case& pc) {
          sim::RunResult r = runner(pc);
          results[i] = sim::to_json(r);
          return r;
        });
      });
    });
    PySweep s;
    const std::size_t status_col = header.size() - 2;
    std::vector<std::string> numeric_cols(header.begin(), header.end() - 2);
    std::vector<double> values;
    values.reserve(rows.size() * numeric_cols.size());
    for (std::size_t i = 0; i < rows.size(); ++i) {
      for (std::size_t j = 0; j < numeric_cols.size(); ++j) values.push_back(field_number(rows[i][j]));
      s.status.push_back(rows[i][status_col]);
      s.errors.push_back(rows[i][status_col + 1]);
      s.summaries.append(s.status.back() == "ok" && results[i] ? to_python(*results[i]) : py::none());
    }
    s.columns = numeric_cols;
    s.data = owned_matrix(std::move(values), static_cast<py::ssize_t>(numeric_cols.size()));
    return s;
  }

 private:
  std::shared_ptr<const sim::Case> case_;
};

}  // namespace

PYBIND11_MODULE(_pcsim, m) {
  m.doc() = "pcsim's C++ core (import pcsim, not this module).";
#if PCSIM_WITH_SIEVE
  sieve::register_sieve();  // the built-in model "sieve", its client, the default model
#endif
  m.attr("__version__") = std::string(version_string());
  m.attr("with_sieve") = static_cast<bool>(PCSIM_WITH_SIEVE);

  py::register_exception_translator([](std::exception_ptr p) {
    try {
      if (p) std::rethrow_exception(p);
    } catch (const py::error_already_set&) {
      throw;
    } catch (const NumericalError& e) {
      raise_numerical(e, py::none());
    } catch (const InputError& e) {
      raise_input(e.what());
    } catch (const IoError& e) {
      raise(pcsim_attr("IoError")(std::string(e.what())));
    } catch (const Error& e) {
      raise(pcsim_attr("Error")(std::string(e.what())));
    }
  });

  py::class_<PyModel>(m, "Model", "A case's model: its declaration and, at the case's parameter "
                                  "values and active constraints, the engine's quantities at a state.")
      .def_property_readonly("name", &PyModel::name, "The model's name (summary.json \"model\").")
      .def_property_readonly("coordinates", &PyModel::coordinates,
                             "The generalized coordinates q, in order.")
      .def_property_readonly("outputs", &PyModel::outputs,
                             "The derived output columns of the time series.")
      .def_property_readonly("active_constraints", &PyModel::active,
                             "The constraints the case activates, in the model's order.")
      .def_property_readonly("period", &PyModel::period,
                             "The excitation period at the case's parameters, s (nan: none).")
      .def_property_readonly("parameters", &PyModel::parameters,
                             "Every parameter: {name: {default, value (the case's), unit, meaning, "
                             "min, max, min_exclusive, max_exclusive}}.")
      .def_property_readonly("constraints", &PyModel::constraints,
                             "The constraints on offer: [{name, kind, active, active_by_default, "
                             "unilateral, friction_of, rough, meaning}].")
      .def("evaluate", &PyModel::evaluate, py::arg("q"), py::arg("qd") = py::none(),
           py::arg("t") = 0.0,
           "The engine's quantities at (t, q, qd) for the case's active constraints: M (n x n), "
           "h, Q (n), g (s x n), g0, gamma (s) with g qd + g0 = 0 and g qdd + gamma = 0, the "
           "reactions R (n) and accelerations qdd (n) as a run computes them, lambda (s) with "
           "R = g^T lambda, and the outputs by name. qd defaults to zeros. Raises ValueError "
           "naming q or qd for a wrong size or a non-finite value, pcsim.NumericalError where "
           "the reactions cannot be solved (e.g. dependent constraints).");

  py::class_<PyRun>(m, "RunResult", "One run of a case: summary.json's content and the time series.")
      .def_readonly("columns", &PyRun::columns, "The time-series columns (timeseries.csv's header).")
      .def_readonly("data", &PyRun::data,
                    "The time series: a 2-D float array, one row per output.dt, one column per "
                    "name in columns (the run's own buffer, not a copy). A switching run's "
                    "mode_<contact> columns hold indices into mode_labels.")
      .def_readonly("summary", &PyRun::summary, "summary.json's content as dicts and lists.")
      .def_readonly("events", &PyRun::events,
                    "With contact.switching, events.csv as {column: array}; else None.")
      .def_readonly("report", &PyRun::report, "The engineer's report pcsim run prints.")
      .def_readonly("complete", &PyRun::complete, "True if the run reached solver.t_end.")
      .def_readonly("mode_labels", &PyRun::mode_labels,
                    "The contact modes the mode_<contact> columns index (switching runs).")
      .def("__getitem__", &PyRun::column, py::arg("column"),
           "A column of the time series by name (a view of data).")
      .def("__contains__", [](const PyRun& r, const std::string& c) {
             return std::find(r.columns.begin(), r.columns.end(), c) != r.columns.end();
           }, "True if the time series has this column.")
      .def("__len__", [](const PyRun& r) { return r.data.shape(0); }, "The number of rows.")
      .def("__repr__", [](const PyRun& r) {
        return "<pcsim.RunResult " + std::to_string(r.data.shape(0)) + " rows x " +
               std::to_string(r.columns.size()) + " columns, complete=" +
               (r.complete ? "True" : "False") + ">";
      });

  py::class_<PySteady>(m, "SteadyResult", "pcsim steady's result: steady.json's content.")
      .def_readonly("data", &PySteady::data, "steady.json's content as dicts and lists.")
      .def_readonly("report", &PySteady::report, "The engineer's report pcsim steady prints.")
      .def("__getitem__", [](const PySteady& s, const std::string& k) { return s.data[py::str(k)]; },
           py::arg("key"), "A key of steady.json.");

  py::class_<PyModes>(m, "ModesResult",
                      "pcsim modes' result: modes.json's content (with vary: modes_vary.json's), the "
                      "eigenvalues and the mode shapes as complex NumPy arrays.")
      .def_readonly("data", &PyModes::data, "modes.json's content (with vary: modes_vary.json's) as dicts and lists.")
      .def_readonly("report", &PyModes::report, "The engineer's report pcsim modes prints.")
      .def_readonly("eigenvalues", &PyModes::eigenvalues,
                    "Every eigenvalue on the tangent space (modes.json's 'eigenvalues', both members of a "
                    "pair), complex128, 1-D; with vary: [step, track], the tracks paired by continuity.")
      .def_readonly("mode_eigenvalues", &PyModes::mode_eigenvalues,
                    "Per mode (modes.json's 'modes': a pair once, its +i member): its eigenvalue, complex128; "
                    "None with vary.")
      .def_readonly("shapes", &PyModes::shapes,
                    "The mode shapes: [mode, coordinate] complex128 (largest component 1), rows aligned "
                    "with mode_eigenvalues, columns with coordinates; None with vary.")
      .def_readonly("coordinates", &PyModes::coordinates, "The coordinates (the columns of shapes).")
      .def_readonly("values", &PyModes::values, "With vary: the key's values (the rows of eigenvalues); else None.")
      .def_readonly("vary", &PyModes::vary, "Whether this is a trace over a key (vary=...).")
      .def("__getitem__", [](const PyModes& s, const std::string& k) { return s.data[py::str(k)]; },
           py::arg("key"), "A key of modes.json (modes_vary.json).");

  py::class_<PyResponse>(m, "ResponseResult",
                         "pcsim response's result: response.csv as a table, response.json.")
      .def_readonly("columns", &PyResponse::columns, "response.csv's header.")
      .def_readonly("data", &PyResponse::data,
                    "response.csv's rows as floats (true/false as 1/0, empty or text fields nan).")
      .def_readonly("text", &PyResponse::text, "response.csv's rows as the text fields written.")
      .def_readonly("meta", &PyResponse::meta, "response.json's content.")
      .def_readonly("summaries", &PyResponse::summaries,
                    "Each point's one-period summary (summary.json's structure), or None.")
      .def("__getitem__", &PyResponse::column, py::arg("column"), "A column by name (a view).")
      .def("__len__", [](const PyResponse& r) { return r.data.shape(0); }, "The number of rows.");

  py::class_<PySweep>(m, "SweepResult",
                      "A sweep's table: sweep.csv's numeric columns, each point's status and summary.")
      .def_readonly("columns", &PySweep::columns,
                    "The varied keys, then the summary columns (sweep.csv without status, error).")
      .def_readonly("data", &PySweep::data,
                    "One row per grid point (grid order, the last axis fastest): floats, "
                    "true/false as 1/0, missing values and failed points nan.")
      .def_readonly("status", &PySweep::status, "Per point: \"ok\" or \"error\".")
      .def_readonly("errors", &PySweep::errors, "Per point: the error message, or \"\".")
      .def_readonly("summaries", &PySweep::summaries,
                    "Per point: summary.json's content, or None where the point failed.")
      .def("__getitem__", &PySweep::column, py::arg("column"), "A column by name (a view).")
      .def("__len__", [](const PySweep& r) { return r.data.shape(0); }, "The number of points.");

  py::class_<PyCheck>(m, "CheckResult",
                      "pcsim check's result: what the engine finds about a case at its initial "
                      "state, without running it. Fields not computed are None.")
      .def_property_readonly("case", [](const PyCheck& c) { return c.r.case_name; }, "The case's name.")
      .def_property_readonly("model", [](const PyCheck& c) { return c.r.model; }, "The model's name.")
      .def_property_readonly("coordinates", [](const PyCheck& c) { return c.r.coordinates; },
                             "The generalized coordinates q (n = len).")
      .def_property_readonly("active_constraints", [](const PyCheck& c) { return c.r.active; },
                             "The active constraints (m = len).")
      .def_property_readonly("mass_positive_definite", [](const PyCheck& c) { return c.r.mass_positive_definite; },
                             "Whether M is positive definite at the initial state (smallest eigenvalue "
                             "> 1e-13 x largest).")
      .def_property_readonly("mass_eigenvalues", [](const PyCheck& c) {
             return py::make_tuple(c.r.mass_eigenvalue_min, c.r.mass_eigenvalue_max);
           }, "M's (smallest, largest) eigenvalue at the initial state.")
      .def_property_readonly("rank", [](const PyCheck& c) { return c.r.rank; },
                             "The rank of the active constraints at the initial state.")
      .def_property_readonly("dof", [](const PyCheck& c) { return c.r.dof; },
                             "The degrees of freedom, n - rank.")
      .def_property_readonly("gruebler", [](const PyCheck& c) { return c.r.gruebler; },
                             "The Gruebler-style count n - m (too low with redundant constraints).")
      .def_property_readonly("redundant", [](const PyCheck& c) { return c.r.redundant; },
                             "The redundant (dependent, consistent) rows, by constraint name.")
      .def_property_readonly("null_space_dimension", [](const PyCheck& c) { return c.r.null_space_dimension; },
                             "m - rank: the dimension of the statically indeterminate part.")
      .def_property_readonly("smallest_singular_value", [](const PyCheck& c) { return c.r.smallest_singular_value; },
                             "The smallest singular value of g, rows scaled to unit length (near 0: "
                             "redundant rows or near a singular position).")
      .def_property_readonly("position_residual", [](const PyCheck& c) { return c.r.position_residual; },
                             "The initial position residual of the holonomic constraints.")
      .def_property_readonly("velocity_residual", [](const PyCheck& c) { return c.r.velocity_residual; },
                             "The initial velocity residual |g qd + g0|.")
      .def_property_readonly("correction", [](const PyCheck& c) {
             return py::make_tuple(c.r.correction_pos, c.r.correction_vel);
           }, "How far the consistent-initial-value correction moves (q, qd): 2-norms.")
      .def_property_readonly("note", [](const PyCheck& c) { return c.r.note; },
                             "The check's remark on accepted dependent rows, or ''.")
      .def_property_readonly("can_run", [](const PyCheck& c) { return c.r.can_run; },
                             "True (a case that cannot run raises pcsim.InputError instead).")
      .def_property_readonly("data", [](const PyCheck& c) { return to_python(sim::to_json(c.r)); },
                             "The report as dicts and lists (null where not computed).")
      .def_readonly("report", &PyCheck::report, "The text pcsim check prints, byte for byte.")
      .def("__repr__", [](const PyCheck& c) {
        return "<pcsim.CheckResult '" + c.r.case_name + "' rank " +
               (c.r.rank ? std::to_string(*c.r.rank) : std::string("?")) + " of " +
               std::to_string(c.r.active.size()) + ", " + std::to_string(c.r.redundant.size()) +
               " redundant>";
      });

  py::class_<PyCase>(m, "Case",
                     "A validated case: a case file, or a model file run with its defaults.")
      .def(py::init(&PyCase::load), py::arg("path"), py::arg("set") = py::none(),
           py::arg("constraints") = py::none(),
           "Loads a case file (or a model file, as pcsim run does) and applies the overrides: "
           "set = {dotted key: value} exactly as --set KEY=VALUE (values as bool, int, float or "
           "the text --set would carry), then constraints = {name: True/False} to switch an "
           "offered constraint or {name: 'expr'} to add a holonomic constraint as --constraint. "
           "Raises pcsim.InputError with the CLI's message, .file and .key.")
      .def("with_set", &PyCase::with_set, py::arg("set") = py::none(),
           py::arg("constraints") = py::none(),
           "A new case: this one with further overrides (the same validation as --set).")
      .def_property_readonly("name", [](const PyCase& c) { return c.get().name; },
                             "The case's name (out/<name> for the CLI).")
      .def_property_readonly("source", [](const PyCase& c) { return c.get().source.string(); },
                             "The file the case was loaded from.")
      .def_property_readonly("model", [](const PyCase& c) { return PyModel(c.shared()); },
                             "The case's model (pcsim.Model), at the case's parameters.")
      .def("to_toml", [](const PyCase& c) { return sim::to_toml(c.get()); },
           "The case as TOML text with every key explicit (pcsim reads it back as this case).")
      .def("run", &PyCase::run, py::arg("out") = py::none(),
           "Runs the case as pcsim run does and returns a pcsim.RunResult; with out, also "
           "writes the same files into that directory. Releases the GIL. Raises "
           "pcsim.NumericalError (with .time, and .result holding what was computed) when the "
           "run fails or its result is unreliable.")
      .def("steady", &PyCase::steady, py::arg("periods") = 1, py::arg("method") = "auto",
           py::arg("max_iterations") = 30, py::arg("transient_periods") = 256,
           py::arg("out") = py::none(),
           "The periodic steady state as pcsim steady finds it; a pcsim.SteadyResult. Releases "
           "the GIL.")
      .def("modes", &PyCase::modes, py::arg("excitation") = py::none(), py::arg("cyclic") = py::none(),
           py::arg("vary") = py::none(), py::arg("out") = py::none(),
           "Natural frequencies, damping ratios and mode shapes about a rest state or a steady "
           "motion, as pcsim modes computes them (the same functions); a pcsim.ModesResult. "
           "excitation = 'off' or a phase in rad (None: the case's [modes] excitation), cyclic = "
           "a list of coordinate names ([]: none, as --no-cyclic; None: the case's [modes] cyclic), "
           "vary = 'KEY=START:STOP:COUNT' traces the eigenvalues over a key (as --vary); with out, "
           "also writes the CLI's files into that directory. Releases the GIL. Raises "
           "pcsim.InputError when the reference is not a rest state or steady motion, "
           "pcsim.NumericalError when the linearization does not exist.")
      .def("response", &PyCase::response, py::arg("vary"), py::arg("periods") = 1,
           py::arg("method") = "auto", py::arg("jobs") = 0, py::arg("summaries") = true,
           py::arg("out") = py::none(),
           "The steady state along one key as pcsim response traces it (vary = "
           "'KEY=START:STOP:COUNT' or 'KEY=v1,v2,...'); a pcsim.ResponseResult. Releases the GIL.")
      .def("check", &PyCase::check,
           "What pcsim check finds at the initial state, without running: a pcsim.CheckResult "
           "(rank, dof, gruebler, redundant rows, smallest singular value, M, residuals, the "
           "correction; .report is the CLI's text). Releases the GIL. Raises pcsim.InputError "
           "with the CLI's message where pcsim check exits 2 (the case cannot run; the report up "
           "to then in the exception's .check_report).")
      .def("sweep", &PyCase::sweep, py::arg("vary"), py::arg("jobs") = 0,
           "Every point of the grid the vary specifications span (a str or a list of "
           "'KEY=START:STOP:COUNT' / 'KEY=v1,v2,...', the last fastest), each computed as pcsim "
           "sweep computes its row, on `jobs` threads (0: all cores); a pcsim.SweepResult. "
           "Releases the GIL.")
      .def("__repr__", [](const PyCase& c) {
        return "<pcsim.Case '" + c.get().name + "' model '" + c.get().model->name() + "'>";
      });
}
