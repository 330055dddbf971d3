// Shared by the animate tests: running pcsim, reading a time series, and loading a page in
// headless chromium (its own profile directory, no background networking, a net log).
#pragma once

#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "../support/cli_util.hpp"

namespace animate_test {

namespace fs = std::filesystem;
using pcsim_test::Result;

inline Result run_pcsim(const std::string& args, const fs::path& cwd) {
  return pcsim_test::sh("'" + pcsim_test::exe() + "' " + args, cwd);
}

/// The time series as columns by name (mode_ columns are left out).
struct Series {
  std::map<std::string, std::vector<double>> col;
  std::map<std::string, std::vector<std::string>> text;
  std::size_t row_at(double t) const {
    const auto& ts = col.at("t");
    std::size_t best = 0;
    for (std::size_t i = 0; i < ts.size(); ++i)
      if (std::abs(ts[i] - t) < std::abs(ts[best] - t)) best = i;
    return best;
  }
};

inline Series read_series(const fs::path& csv) {
  Series s;
  std::ifstream in(csv);
  std::string line;
  std::getline(in, line);
  std::vector<std::string> names;
  std::stringstream hs(line);
  for (std::string c; std::getline(hs, c, ',');) names.push_back(c);
  while (std::getline(in, line)) {
    std::stringstream ls(line);
    std::size_t i = 0;
    for (std::string c; std::getline(ls, c, ','); ++i) {
      if (names[i].rfind("mode_", 0) == 0) s.text[names[i]].push_back(c);
      else s.col[names[i]].push_back(c.empty() ? NAN : std::stod(c));
    }
  }
  return s;
}

inline std::string chromium() { return "/usr/bin/chromium"; }

/// Loads `page` (with its fragment) in headless chromium and returns the page's state (what it
/// drew: <pre id="pcsim-state">); with `netlog`, chromium logs its network events there.
inline nlohmann::json page_state(const fs::path& page, const std::string& fragment, const fs::path& scratch,
                                 const fs::path& netlog = {}) {
  static int n = 0;
  const fs::path profile = scratch / ("chromium-profile-" + std::to_string(n++));
  std::string cmd = "timeout 60 '" + chromium() + "' --headless --no-sandbox --disable-gpu "
                    "--no-first-run --disable-background-networking --disable-component-update "
                    "--disable-sync --disable-default-apps --disable-extensions "
                    "--user-data-dir='" + profile.string() + "' ";
  if (!netlog.empty()) cmd += "--log-net-log='" + netlog.string() + "' --net-log-capture-mode=Everything ";
  cmd += "--dump-dom 'file://" + fs::absolute(page).string() + "#" + fragment + "' 2>/dev/null";
  const Result r = pcsim_test::sh(cmd, scratch);
  const std::string open = "<pre id=\"pcsim-state\" hidden=\"\">";
  const auto a = r.out.find(open);
  if (a == std::string::npos) return nlohmann::json();
  const auto b = r.out.find("</pre>", a);
  std::string text = r.out.substr(a + open.size(), b - a - open.size());
  // The DOM dump escapes &, < and > in text.
  for (const auto& [from, to] : std::vector<std::pair<std::string, std::string>>{{"&quot;", "\""}, {"&lt;", "<"}, {"&gt;", ">"}, {"&amp;", "&"}}) {
    for (std::size_t p = 0; (p = text.find(from, p)) != std::string::npos; p += to.size()) text.replace(p, from.size(), to);
  }
  return nlohmann::json::parse(text, nullptr, false);
}

/// The requests a page made (the renderer's resource loads, traffic annotation 101845102
/// "blink_resource_loader", in chromium's net log): their URLs.
inline std::vector<std::string> page_requests(const fs::path& netlog) {
  std::vector<std::string> urls;
  std::ifstream in(netlog);
  const nlohmann::json log = nlohmann::json::parse(in, nullptr, false);
  if (!log.is_object() || !log.contains("events")) return {"<no net log>"};
  std::map<long, std::string> url_of;  // by source id
  for (const auto& e : log["events"]) {
    if (!e.contains("params") || !e.contains("source")) continue;
    const auto& p = e["params"];
    const long id = e["source"].value("id", -1L);
    if (p.contains("url") && p["url"].is_string()) url_of[id] = p["url"].get<std::string>();
    if (p.contains("traffic_annotation") && p["traffic_annotation"] == 101845102)
      urls.push_back(url_of.count(id) ? url_of[id] : std::string("<request>"));
  }
  return urls;
}

}  // namespace animate_test
