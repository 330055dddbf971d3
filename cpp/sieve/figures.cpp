// The sieve's figures of `pcsim plot`: theta(t), R_u(t) with 0 marked, f*(t) with f marked, x(t)
// and y(t), and with switching contacts the roller's height over the deck u(t) - u0.
#include "sieve/run.hpp"

#include "common/error.hpp"

namespace pcsim::sieve {

std::vector<sim::PlotFigure> sieve_figures(const nlohmann::json& s,
                                           const std::set<std::string>& columns,
                                           const std::string& table) {
  for (const char* need : {"x", "y", "theta", "R_u", "fstar"})
    if (!columns.count(need))
      throw InputError(table + ": header has no column '" + need + "'");
  double f = 0;
  bool have_f = false;
  if (s.contains("assumptions") && s["assumptions"].contains("parameters.f")) {
    f = s["assumptions"]["parameters.f"].get<double>();
    have_f = true;
  }
  std::vector<sim::PlotFigure> figs;
  figs.push_back({"theta.png", "Desk rotation theta(t)", "theta [rad]", {{"theta", "theta"}}, "", 0, false});
  figs.push_back({"R_u.png", "Normal contact force R_u(t); (3.1) contact kept while R_u > 0",
                  "R_u [N]", {{"R_u", "R_u"}}, "R_u = 0 (contact lost)", 0, true});
  figs.push_back({"fstar.png", "Friction ratio f*(t) = |R_s|/R_u; (3.2) rolling kept while f* < f",
                  "f* [-]", {{"fstar", "f*"}}, "f (friction coefficient)", f, have_f, false});
  figs.push_back({"xy.png", "Desk displacement x(t) (vertical) and y(t) (horizontal)",
                  "displacement [m]", {{"x", "x"}, {"y", "y"}}, "", 0, false});
  if (s.contains("switching") && columns.count("u")) {
    double u0 = 0;
    bool have_u0 = false;
    if (s.contains("parameters") && s["parameters"].contains("u0")) {
      u0 = s["parameters"]["u0"].get<double>();
      have_u0 = true;
    }
    sim::PlotFigure fu{"u.png", "Roller height over the deck u(t) - u0 (the gap; 0: on the deck)",
                       "u - u0 [micrometres]", {{"u", "u - u0"}}, "on the deck", 0.0, true};
    fu.offset = have_u0 ? u0 : 0.0;
    fu.scale = 1e6;
    figs.push_back(fu);
  }
  return figs;
}

}  // namespace pcsim::sieve
