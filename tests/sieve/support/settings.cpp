// Reading SieveSettings out of a validated sieve case (settings.hpp).
#include "sieve/support/settings.hpp"

namespace pcsim::sieve {

SieveSettings settings_from_table(const toml::table& t) {
  SieveSettings s;
  auto par = [&](const char* name) { return *t["parameters"][name].value<double>(); };
  SieveParameters& p = s.p;
  p.m0 = par("m0"); p.m1 = par("m1"); p.m2 = par("m2");
  p.J0 = par("J0"); p.J1 = par("J1"); p.J2 = par("J2");
  p.r = par("r"); p.e = par("e");
  p.cx = par("cx"); p.cy = par("cy"); p.ctheta = par("ctheta");
  p.bx = par("bx"); p.by = par("by"); p.btheta = par("btheta");
  p.omega = par("omega"); p.g = par("g");
  p.x0 = par("x0"); p.y0 = par("y0"); p.xc = par("xc"); p.yc = par("yc");
  p.xb = par("xb"); p.yb = par("yb"); p.a = par("a"); p.b = par("b");
  p.u0 = par("u0"); p.f = par("f");
  s.constraints.contact = *t["constraints"]["contact"].value<bool>();
  s.constraints.rolling = *t["constraints"]["rolling"].value<bool>();
  s.constraints.lock_theta = *t["constraints"]["lock_theta"].value<bool>();
  s.constraints.rolling_as_printed = *t["constraints"]["rolling_as_printed"].value<bool>();
  const toml::node_view<const toml::node> ini = t["initial"];
  const double s0 = *ini["s0"].value<double>();
  const std::array<double, 6> q_default = {0, 0, 0, s0, p.u0, 0};
  for (int i = 0; i < 6; ++i) {
    const std::string name = kCoordinateNames[i];
    s.q0[i] = ini[name].value_or(q_default[i]);
    s.qd0[i] = ini[name + "_d"].value_or(0.0);
  }
  s.solver.kernel = *parse_kernel(*t["solver"]["kernel"].value<std::string>());
  s.solver.form = *t["solver"]["form"].value<std::string>() == "ode" ? Form::ode : Form::dae;
  s.solver.rtol = *t["solver"]["rtol"].value<double>();
  s.solver.atol = *t["solver"]["atol"].value<double>();
  s.solver.t_end = *t["solver"]["t_end"].value<double>();
  s.solver.h0 = *t["solver"]["h0"].value<double>();
  s.output.dt = *t["output"]["dt"].value<double>();
  s.output.summary_periods = static_cast<int>(t["output"]["summary_periods"].value_or(int64_t{5}));
  return s;
}

}  // namespace pcsim::sieve
