// `pcsim response` for a case (see response.hpp).
#include "steady/response.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <mutex>
#include <set>

#include "common/error.hpp"
#include "common/files.hpp"
#include "common/format.hpp"
#include "common/parallel.hpp"
#include "sim/client.hpp"
#include "sim/vary.hpp"

namespace pcsim::steady {

namespace {

std::string text(double v) { return csv_number(v); }

}  // namespace

sim::Case case_at(const sim::Case& c, const std::string& key, double value) {
  sim::Case out = c;
  const auto dot = key.find('.');
  const std::string section = key.substr(0, dot), name = key.substr(dot + 1);
  toml::table* t = out.table[section].as_table();
  if (!t) throw InputError("--vary " + key + ": no table [" + section + "]");
  t->insert_or_assign(name, value);
  sim::retype(out);
  return out;
}

ResponseResult response_case(const sim::Case& c, const ResponseOptions& o) {
  ResponseResult res;
  const auto t_start = std::chrono::steady_clock::now();
  const sim::Axis axis = sim::parse_vary(o.vary, c);
  res.key = axis.key;
  const auto eq = o.vary.find('=');
  const std::string values = o.vary.substr(eq + 1);
  res.continuation = values.find(':') != std::string::npos;
  std::vector<double> listed;
  for (const auto& t : axis.texts) listed.push_back(std::stod(t));
  const CaseOrbit base(c, o.periods, axis.key);  // checks the case and the key
  // The orbit period (and with it the step budget's feasibility) moves with the key: checked
  // at the smallest and the largest value before any work (CaseOrbit refuses an infeasible one).
  if (!listed.empty()) {
    const auto [lo, hi] = std::minmax_element(listed.begin(), listed.end());
    const CaseOrbit at_lo(case_at(c, axis.key, *lo), o.periods);
    const CaseOrbit at_hi(case_at(c, axis.key, *hi), o.periods);
  }
  std::unique_ptr<OutputDirectory> out;
  if (o.out_dir) out = std::make_unique<OutputDirectory>(*o.out_dir, "response");
  ShootingOptions so = shooting_options(base.setup(), o.method);

  if (res.continuation) {
    ContinuationOptions co;
    co.p_start = listed.front();
    co.p_stop = listed.back();
    co.count = static_cast<int>(listed.size());
    co.shooting = so;
    const auto problem_at = [&base](double p) { return base.problem(p); };
    const auto derivative_at = [&base](double p) { return base.derivative(p); };
    // The start: Newton from the case's start (or equilibrium) at p_start.
    const CaseOrbit first(case_at(c, axis.key, co.p_start), o.periods);
    const Branch br = continue_branch(problem_at, derivative_at, first.guess(), co);
    res.complete = br.complete;
    res.message = br.message;
    if (br.points.empty())
      throw NumericalError("pcsim response: no orbit at " + axis.key + " = " + axis.texts.front() +
                               ": " + br.message, 0.0);
    for (const auto& bp : br.points) {
      ResponsePoint rp;
      rp.p = bp.p;
      rp.ok = true;
      rp.x = bp.x;
      rp.floquet = bp.floquet;
      rp.iterations = bp.iterations;
      rp.residual = bp.residual;
      rp.fold_before = bp.fold_before;
      rp.fold_p = bp.fold_p;
      res.points.push_back(rp);
    }
  } else {
    res.points.resize(listed.size());
    parallel_for(listed.size(), o.jobs, [&](std::size_t i) {
      ResponsePoint& rp = res.points[i];
      rp.p = listed[i];
      try {
        const CaseOrbit orbit(case_at(c, axis.key, listed[i]), o.periods);
        const OrbitResult r = find_orbit(orbit.problem(), orbit.guess(), so);
        if (!r.converged) throw NumericalError(r.message, 0.0);
        rp.ok = true;
        rp.x = r.point;
        rp.floquet = r.floquet;
        rp.iterations = static_cast<int>(r.history.size());
        rp.residual = r.residual;
      } catch (const std::exception& e) {
        rp.error = e.what();
      }
    });
  }

  // The one-period summary of every orbit: independent, in parallel.
  if (o.summaries) {
    parallel_for(res.points.size(), o.jobs, [&](std::size_t i) {
      ResponsePoint& rp = res.points[i];
      if (!rp.ok) return;
      try {
        const CaseOrbit orbit(case_at(c, axis.key, rp.p), o.periods);
        OrbitResult r;
        r.point = rp.x;
        rp.summary = period_summary(orbit, r);
      } catch (const std::exception& e) {
        rp.ok = false;
        rp.error = std::string("the period summary: ") + e.what();
      }
    });
  }

  // response.csv
  const auto& coords = c.model->coordinates();
  const auto held = base.held();
  std::vector<std::string> react, outputs;
  for (const auto& q : coords) react.push_back("R_" + q);
  for (const auto& q : c.model->outputs()) outputs.push_back(q);
  // Reactions that are zero at every point (ideal rows of unconstrained coordinates) are left out.
  std::vector<std::string> react_kept;
  for (const auto& r : react) {
    bool nonzero = false;
    for (const auto& p : res.points)
      if (p.ok && p.summary && p.summary->extremes.count(r)) {
        const sim::ColumnExtremes& e = p.summary->extremes.at(r);
        nonzero = nonzero || (std::isfinite(e.min) && e.min != 0.0) ||
                  (std::isfinite(e.max) && e.max != 0.0);
      }
    if (nonzero) react_kept.push_back(r);
  }
  const std::vector<std::string> client_keys = {"R_u_min", "R_u_max", "R_u_min_over_weight",
                                                "fstar_max", "theta_mean"};
  std::vector<std::string> client_present, derived_present;
  for (const auto& p : res.points) {
    if (!p.ok || !p.summary) continue;
    for (const auto& k : client_keys)
      if (p.summary->additions.contains(k) && std::find(client_present.begin(), client_present.end(), k) == client_present.end())
        client_present.push_back(k);
    if (c.client) {
      const sim::Case pc = case_at(c, axis.key, p.p);
      for (const auto& [k, v] : c.client->derived_columns(*p.summary, pc))
        if (std::find(derived_present.begin(), derived_present.end(), k) == derived_present.end())
          derived_present.push_back(k);
    }
  }
  res.columns = {"point", axis.key, "status", "stable", "max_multiplier", "fold_before", "fold_at",
                 "newton_iterations", "residual"};
  for (const auto& q : coords) res.columns.push_back("amplitude." + q);
  for (const auto& r : react_kept) {
    res.columns.push_back("min." + r);
    res.columns.push_back("max." + r);
  }
  for (const auto& q : outputs) {
    res.columns.push_back("min." + q);
    res.columns.push_back("max." + q);
  }
  for (const auto& k : client_present) res.columns.push_back(k);
  for (const auto& k : derived_present) res.columns.push_back(k);
  for (const auto& h : held) {
    res.columns.push_back("holding_force." + h);
  }
  res.columns.push_back("error");
  for (std::size_t i = 0; i < res.points.size(); ++i) {
    const ResponsePoint& p = res.points[i];
    std::vector<std::string> row = {std::to_string(i), text(p.p), p.ok ? "ok" : "error"};
    if (!p.ok) {
      row.resize(res.columns.size());
      row.back() = p.error;
      res.rows.push_back(row);
      continue;
    }
    row.push_back(p.floquet.stable ? "1" : "0");
    row.push_back(text(p.floquet.max_modulus));
    row.push_back(p.fold_before ? "1" : "0");
    row.push_back(p.fold_before ? text(p.fold_p) : "");
    row.push_back(std::to_string(p.iterations));
    row.push_back(text(p.residual));
    const sim::RunResult* s = p.summary ? &*p.summary : nullptr;
    auto ex = [&](const std::string& col, double (*what)(const sim::ColumnExtremes&)) {
      if (!s || !s->extremes.count(col)) return std::string();
      const double v = what(s->extremes.at(col));
      return std::isfinite(v) ? text(v) : std::string();
    };
    auto amplitude = [](const sim::ColumnExtremes& e) { return e.amplitude(); };
    auto min = [](const sim::ColumnExtremes& e) { return e.min; };
    auto max = [](const sim::ColumnExtremes& e) { return e.max; };
    for (const auto& q : coords) row.push_back(ex(q, amplitude));
    for (const auto& r : react_kept) {
      row.push_back(ex(r, min));
      row.push_back(ex(r, max));
    }
    for (const auto& q : outputs) {
      row.push_back(ex(q, min));
      row.push_back(ex(q, max));
    }
    for (const auto& k : client_present)
      row.push_back(s && s->additions.contains(k) && s->additions[k].is_number()
                        ? text(s->additions[k].get<double>())
                        : "");
    std::map<std::string, double> derived;
    if (c.client && s) derived = c.client->derived_columns(*s, case_at(c, axis.key, p.p));
    for (const auto& k : derived_present) row.push_back(derived.count(k) ? text(derived[k]) : "");
    for (std::size_t k = 0; k < held.size(); ++k)
      row.push_back(k < static_cast<std::size_t>(p.x.H.size()) ? text(p.x.H[k]) : "");
    row.push_back("");
    res.rows.push_back(row);
  }

  // response.json: folds, resonances (local maxima of each coordinate's amplitude), the
  // smallest contact margin.
  nlohmann::json meta;
  meta["case"] = c.name;
  meta["model"] = c.model->name();
  meta["key"] = axis.key;
  meta["mode"] = res.continuation ? "pseudo-arclength continuation" : "listed values";
  meta["values"] = {listed.front(), listed.back(), static_cast<int>(listed.size())};
  meta["complete"] = res.complete;
  meta["message"] = res.message;
  meta["points"] = static_cast<int>(res.points.size());
  meta["periods"] = o.periods;
  nlohmann::json folds = nlohmann::json::array();
  for (std::size_t i = 0; i < res.points.size(); ++i)
    if (res.points[i].fold_before) folds.push_back({{"point", i}, {"at", res.points[i].fold_p}});
  meta["folds"] = folds;
  // A resonance: a local maximum of a coordinate's amplitude along the branch that stands out
  // (its prominence, the drop to the lower of the deepest values on either side before a higher
  // point, is at least 1 % of it) and is not rounding noise (at least 1e-6 of the largest
  // amplitude of any coordinate at that point: a constrained coordinate's amplitude is noise).
  nlohmann::json resonances = nlohmann::json::array();
  const int col_amp0 = 9;
  const std::size_t nrows = res.rows.size();
  std::vector<std::vector<double>> amp(coords.size(), std::vector<double>(nrows, NAN));
  for (std::size_t q = 0; q < coords.size(); ++q)
    for (std::size_t i = 0; i < nrows; ++i)
      if (!res.rows[i][col_amp0 + q].empty()) amp[q][i] = std::stod(res.rows[i][col_amp0 + q]);
  for (std::size_t q = 0; q < coords.size(); ++q) {
    const auto& a = amp[q];
    for (std::size_t i = 1; i + 1 < nrows; ++i) {
      if (!(a[i] > a[i - 1] && a[i] > a[i + 1])) continue;
      double largest = 0;
      for (std::size_t r = 0; r < coords.size(); ++r)
        if (std::isfinite(amp[r][i])) largest = std::max(largest, amp[r][i]);
      if (!(a[i] >= 1e-6 * largest)) continue;
      double left = a[i], right = a[i];
      for (std::size_t j = i; j-- > 0 && !(a[j] > a[i]);) left = std::min(left, a[j]);
      for (std::size_t j = i + 1; j < nrows && !(a[j] > a[i]); ++j) right = std::min(right, a[j]);
      if (a[i] - std::max(left, right) < 0.01 * a[i]) continue;
      resonances.push_back({{"coordinate", coords[q]}, {"point", i}, {"at", res.points[i].p}, {"amplitude", a[i]}});
    }
  }
  meta["resonances"] = resonances;
  auto it = std::find(res.columns.begin(), res.columns.end(), "contact_margin");
  if (it != res.columns.end()) {
    const std::size_t col = it - res.columns.begin();
    double best = INFINITY;
    std::size_t at = 0;
    for (std::size_t i = 0; i < res.rows.size(); ++i)
      if (!res.rows[i][col].empty() && std::stod(res.rows[i][col]) < best) best = std::stod(res.rows[i][col]), at = i;
    if (std::isfinite(best)) meta["smallest_contact_margin"] = {{"at", res.points[at].p}, {"margin", best}};
  }
  int unstable = 0, failed = 0;
  for (const auto& p : res.points) {
    if (!p.ok) ++failed;
    else if (!p.floquet.stable) ++unstable;
  }
  meta["unstable_points"] = unstable;
  meta["failed_points"] = failed;
  meta["wall_seconds"] = std::chrono::duration<double>(std::chrono::steady_clock::now() - t_start).count();
  res.meta = meta;

  if (out) {
    std::string csv;
    for (std::size_t i = 0; i < res.columns.size(); ++i) csv += (i ? "," : "") + res.columns[i];
    csv += "\n";
    for (const auto& row : res.rows) {
      for (std::size_t i = 0; i < row.size(); ++i) {
        std::string f = row[i];
        if (f.find_first_of(",\"\n") != std::string::npos) {
          std::string q = "\"";
          for (char ch : f) q += ch == '"' ? std::string("\"\"") : std::string(1, ch == '\n' ? ' ' : ch);
          f = q + "\"";
        }
        csv += (i ? "," : "") + f;
      }
      csv += "\n";
    }
    out->write("response.csv", csv);
    out->write("response.json", meta.dump(2) + "\n");
    out->commit();
  }
  return res;
}

}  // namespace pcsim::steady
