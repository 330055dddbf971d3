#include "sim/rank_summary.hpp"

#include <cmath>
#include <sstream>

#include "common/format.hpp"

namespace pcsim::sim {

namespace {

nlohmann::json names(const std::vector<int>& rows, const std::vector<std::string>& active) {
  nlohmann::json out = nlohmann::json::array();
  for (int r : rows)
    if (r >= 0 && r < static_cast<int>(active.size())) out.push_back(active[static_cast<std::size_t>(r)]);
  return out;
}

std::string list(const nlohmann::json& a) {
  std::string s;
  for (const auto& n : a) s += (s.empty() ? "'" : ", '") + n.get<std::string>() + "'";
  return s.empty() ? std::string("(not told)") : s;
}

}  // namespace

nlohmann::json rank_summary(const mech::SimulationResult& r, const std::vector<std::string>& active,
                            double t0) {
  const int s = static_cast<int>(active.size());
  if (s == 0 || (r.rank_start >= s && r.rank_changes.empty())) return nullptr;
  nlohmann::json j;
  j["rows"] = s;
  j["rank_start"] = r.rank_start;
  j["threshold"] = mech::kRankReport;
  j["dependent_start"] = names(r.dependent_start, active);
  if (r.rank_start < s)
    j["indeterminate"] = {{"from", t0},
                          {"nullity", s - r.rank_start},
                          {"rows", names(r.dependent_start, active)}};
  nlohmann::json ch = nlohmann::json::array();
  for (const mech::RankChange& c : r.rank_changes) {
    nlohmann::json e = {{"t", c.t},
                        {"t_from", c.t_from},
                        {"rank_before", c.rank_before},
                        {"rank", c.rank},
                        {"sigma", c.sigma},
                        {"dependent", names(c.rows, active)}};
    e["t_to"] = std::isfinite(c.t_to) ? nlohmann::json(c.t_to) : nlohmann::json(nullptr);
    ch.push_back(e);
  }
  j["changes"] = ch;
  return j;
}

std::vector<std::pair<double, std::string>> rank_event_rows(const nlohmann::json& rank) {
  std::vector<std::pair<double, std::string>> out;
  if (rank.is_null()) return out;
  for (const auto& c : rank["changes"]) {
    const std::string before = std::to_string(c["rank_before"].get<int>());
    const std::string at = std::to_string(c["rank"].get<int>());
    nlohmann::json rows = c["dependent"];
    if (rows.empty()) rows.push_back("");
    for (const auto& n : rows) {
      std::string line;
      const double t0 = c["t_from"].get<double>();
      append_number(line, t0);
      line += ",rank_lost," + n.get<std::string>() + "," + before + "," + at + ",,,,,,,\n";
      out.emplace_back(t0, line);
      if (!c["t_to"].is_null()) {
        const double t1 = c["t_to"].get<double>();
        line.clear();
        append_number(line, t1);
        line += ",rank_regained," + n.get<std::string>() + "," + at + "," + before + ",,,,,,,\n";
        out.emplace_back(t1, line);
      }
    }
  }
  return out;
}

std::string rank_report(const nlohmann::json& rank) {
  if (rank.is_null()) return "";
  std::ostringstream os;
  const int s = rank["rows"].get<int>(), r0 = rank["rank_start"].get<int>();
  os << "  rank of the active constraints: " << r0 << " of " << s << " at the start";
  if (r0 < s)
    os << " (" << list(rank["dependent_start"]) << " redundant: the split of R among the "
       << "constraints is indeterminate, null space of dimension " << (s - r0)
       << "; lambda is the minimum-norm split)";
  const auto& ch = rank["changes"];
  if (ch.empty()) {
    os << ", unchanged over the run\n";
    return os.str();
  }
  os << "; lost " << ch.size() << (ch.size() == 1 ? " time" : " times")
     << " (singular positions, sigma_min/sigma_max < " << format_significant(rank["threshold"].get<double>(), 3)
     << "):\n";
  std::size_t shown = 0;
  for (const auto& c : ch) {
    if (++shown > 10) {
      os << "    ... (" << ch.size() - 10 << " more in summary.json)\n";
      break;
    }
    os << "    t = " << format_significant(c["t"].get<double>(), 9) << " s: rank "
       << c["rank"].get<int>() << ", " << list(c["dependent"]) << " dependent";
    if (c["t_to"].is_null())
      os << " to the end of the run\n";
    else
      os << " (t = " << format_significant(c["t_from"].get<double>(), 12) << " .. "
         << format_significant(c["t_to"].get<double>(), 12) << " s)\n";
  }
  return os.str();
}

}  // namespace pcsim::sim
