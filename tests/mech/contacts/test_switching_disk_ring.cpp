// A disk rolling on a circle (issue 22: the planar `rolling` joint with surface = "circle"), with
// switching contacts: inside a ring (models/contact/disk_ring_bodies.toml) and outside a drum
// (the body model below), fixed, turning or driven, each at the origin and with the circle's
// centre at (1000, -500) m. A uniform disk, J = m r^2/2 (k = J/(m r^2) = 1/2). Oracles:
//  - in a ring (L = R - r, psi from the bottom): 3/2 L psi_dd = -g sin(psi), the period
//    4 sqrt(3 L/(2 g)) K(sin(psi0/2)) (2 pi sqrt(3 L/(2 g)) for small swings), and the same
//    equation by this test's RK4; energy; the no-slip relation L psi_d + r th_d = R Omega;
//  - off a drum (L = R + r, th from the top): the rolling solution's contact force
//    N = m g ((3 + k) cos(th) - b)/(1 + k), friction m g k sin(th)/(1 + k) against the motion,
//    b = 2 cos(th0) + (1 + k) v0^2/(g L); it slips where friction = mu_s N (a quadratic in
//    cos(th)) and would lift off at cos(th) = b/(3 + k) (4/7 from rest at the top);
//  - a driven drum: the same physics written by hand in the energy form;
//  - a disk dropped in a ring: impacts with Newton's restitution as the bouncing ball's series.
#define BOOST_TEST_MODULE switching_disk_ring
#include <boost/test/unit_test.hpp>

#include <algorithm>
#include <cmath>
#include <string>

#include "switching_util.hpp"
#include "../../support/pendulum_rk4.hpp"

using namespace switching_test;

namespace {
constexpr double kG = 9.81, kM = 1.0, kR = 0.1, kJ = 0.005, kRing = 0.5, kK = kJ / (kM * kR * kR);

struct Place {
  double X0, Y0;
};
const Place kPlaces[] = {{0.0, 0.0}, {1000.0, -500.0}};

int column(const Model& m, const std::string& name) {
  const auto& n = m.derived_names();
  const auto it = std::find(n.begin(), n.end(), name);
  BOOST_REQUIRE_MESSAGE(it != n.end(), "no output " << name);
  return static_cast<int>(it - n.begin());
}

// The drum models' parameters (the disk's m, r, J; the circle's R and centre X0, Y0; friction; the
// drum's motion A sin(w t)).
const std::string kParameters = R"([model.parameters]
m = 1.0
r = 0.1
J = 0.005
R = 0.5
g = 9.81
mu_s = 0.6
mu_k = 0.6
X0 = 0.0
Y0 = 0.0
A = 0.0
w = 0.0
)";

// A disk (m, r, J) on the circle of radius R of a drum turned about its centre (X0, Y0) by
// `motion` (an expression of t; "" = the circle is ground's), outside it or inside, rolling with
// Coulomb friction mu_s, mu_k. Coordinates disk_x, disk_y, disk_th.
std::string body_model(bool inside, const std::string& motion) {
  std::string s = "[model]\nname = \"drum\"\n" + kParameters + R"([model.body.ground]
markers = { hub = ["X0", "Y0"] }
[model.body.disk]
mass = "m"
inertia = "J"
[model.joint.roll]
type = "rolling"
)";
  s += motion.empty() ? "marker1 = \"hub\"\n" : "body1 = \"drum\"\n";
  s += std::string("body2 = \"disk\"\nradius = \"r\"\nsurface = \"circle\"\ncircle_radius = \"R\"\ninside = ") +
       (inside ? "true" : "false") + "\nunilateral = true\nmu_static = \"mu_s\"\nmu_kinetic = \"mu_k\"\n";
  s += "[model.force.gravity]\ntype = \"gravity\"\ng = [0, \"-g\"]\n";
  if (!motion.empty())
    s += "[model.body.drum]\nmass = 10.0\ninertia = 2.5\n[model.joint.turn]\ntype = \"revolute\"\nmarker1 = \"hub\"\n"
         "body2 = \"drum\"\nmotion = [\"" + motion + "\"]\n";
  return s;
}

// The same machine written by hand in the energy form (coordinates x, y, th; the drum's rate
// `rate` = d(motion)/dt by hand). With rho = |c - O|, e = (c - O)/rho and e' = (-e_y, e_x), the
// contact point's sliding velocity along the joint's tangent (n_y, -n_x), n = e outside and -e
// inside, relative to the drum's material point there:
//   outside: -e'.v + r th_d + rate (rho - r);   inside: e'.v + r th_d - rate (rho + r).
std::string energy_model(bool inside, const std::string& rate) {
  const std::string rho = "sqrt((x - X0)^2 + (y - Y0)^2)";
  const std::string sg = inside ? "" : "-";
  std::string s = "[model]\nname = \"drum_energy\"\ncoordinates = [\"x\", \"y\", \"th\"]\n" + kParameters + R"([model.energy]
kinetic = "0.5*m*(x_d^2 + y_d^2) + 0.5*J*th_d^2"
potential = "m*g*y"
[[model.constraint]]
name = "contact"
)";
  s += "holonomic = \"" + (inside ? "R - r - " + rho : rho + " - (R + r)") + "\"\nunilateral = true\n";
  s += "[[model.constraint]]\nname = \"rolling\"\n";
  s += "velocity = { x = \"" + sg + "(Y0 - y)/" + rho + "\", y = \"" + sg + "(x - X0)/" + rho + "\", th = \"r\" }\n";
  s += "velocity0 = \"" + (inside ? "-(" + rate + ")*(" + rho + " + r)" : "(" + rate + ")*(" + rho + " - r)") + "\"\n";
  s += "friction = \"contact\"\nmu_static = \"mu_s\"\nmu_kinetic = \"mu_k\"\n";
  return s;
}

std::shared_ptr<const Model> model_of(const std::string& text, const std::map<std::string, double>& p,
                                      const Eigen::VectorXd& q0) {
  return modelfile::load_model_text(text, "drum.toml")->instantiate(p, q0, 0.0);
}

// The state at an event: the trace's step end at its instant (a switch ends a step there).
Eigen::VectorXd q_at(const Trace& tr, double t) {
  for (std::size_t i = 0; i < tr.t.size(); ++i)
    if (std::abs(tr.t[i] - t) <= 1e-12) return tr.q[i];
  BOOST_FAIL("no step ends at the event t = " << t);
  return {};
}

}  // namespace

// A disk released from rest at psi0 from the bottom of a fixed ring (friction enough to roll
// all the way: mu = 1, the friction it needs, tan(psi)/3, stays below 0.86). Its centre swings as
// the reduced pendulum 3/2 L psi_dd = -g sin(psi), L = R - r: the zero crossings of psi (found on
// the integrator's dense output by bisection) are a period apart two by two, the period
// 4 sqrt(3 L/(2 g)) K(sin(psi0/2)) (the small swing's 2 pi sqrt(3 L/(2 g)) = 1.2708 s times 1 +
// psi0^2/16 + ...); psi(t) follows the RK4 solution (h = 1e-4 s, its error < 1e-12 rad); no event;
// the energy stays; and the rolling relation L psi_d + r th_d = R Omega holds. The same in a ring
// turning at Omega = 3 rad/s (the disk set spinning at R Omega/r): a constant rate changes
// nothing of the swing (the energy is then not the fixed ring's: the drive works on the spin).
// Tolerances are the integration's at rtol = atol = 1e-10 (observed worst in brackets): psi
// 1e-7 rad (3.2e-8, in the turning ring, whose disk spins at 15 rad/s; 2.6e-9 in the fixed one),
// the period 1e-8 s (1.9e-9: bisection on Radau's dense output), the energy 2e-8 of m g L
// (8.1e-9), the rolling relation 3e-8 m/s (8.3e-9), the gap 2e-8 m (8.0e-9).
BOOST_AUTO_TEST_CASE(disk_in_a_ring_swings_with_the_rolling_pendulums_period) {
  const double L = kRing - kR;
  const double T0 = 2 * M_PI * std::sqrt(1.5 * L / kG);
  for (const Place& pl : kPlaces)
    for (double Omega : {0.0, 3.0})
      for (double psi0 : {0.02, 1.2}) {
        BOOST_TEST_CONTEXT("centre (" << pl.X0 << ", " << pl.Y0 << "), Omega " << Omega << ", psi0 " << psi0) {
          const double T = 4 * std::sqrt(1.5 * L / kG) * std::comp_ellint_1(std::sin(psi0 / 2));
          const Eigen::Vector3d q0(pl.X0 + L * std::sin(psi0), pl.Y0 - L * std::cos(psi0), 0.0);
          const Eigen::Vector3d qd0(0.0, 0.0, kRing * Omega / kR);
          auto m = contact_model("disk_ring_bodies",
                                 {{"X0", pl.X0}, {"Y0", pl.Y0}, {"Omega", Omega}, {"mu_s", 1.0}, {"mu_k", 1.0}}, q0);
          const int iE = column(*m, "energy"), iS = column(*m, "slip"), iGap = column(*m, "gap");
          auto psi_of = [&](const Eigen::VectorXd& q) { return std::atan2(q[0] - pl.X0, -(q[1] - pl.Y0)); };
          SimulationOptions o;
          o.rtol = o.atol = 1e-10;
          o.t_end = 2.6 * T;
          o.active_constraints = all_constraints(*m);
          std::vector<double> crossings;
          double th = psi0, thd = 0.0, t_rk = 0.0, err_psi = 0.0, err_E = 0.0, err_slip = 0.0, err_gap = 0.0;
          double E0 = NAN;
          const double dt = 0.01, h = 1e-4;
          int next = 0;
          const auto acc = [&](double a) { return -kG * std::sin(a) / (1.5 * L); };
          const auto r = simulate_switching(*m, q0, qd0, o, {}, [&](const StepView& v, const std::vector<ContactMode>&) {
            for (; next * dt <= v.t; ++next) {
              const Sample& s = v.sample(std::max(v.t_prev, next * dt));
              while (t_rk < s.t - 1e-12) {
                pcsim::testing::rk4_step(th, thd, h, acc);
                t_rk += h;
              }
              if (std::isnan(E0)) E0 = s.derived[iE];
              err_psi = std::max(err_psi, std::abs(psi_of(s.q) - th));
              err_E = std::max(err_E, std::abs(s.derived[iE] - E0));
              err_slip = std::max(err_slip, std::abs(s.derived[iS]));
              err_gap = std::max(err_gap, std::abs(s.derived[iGap]));
            }
            double a = v.t_prev, b = v.t;
            const double pa = psi_of(v.sample(a).q), pb = psi_of(v.sample(b).q);
            if (pa != 0.0 && (pa > 0) != (pb > 0)) {
              for (int it = 0; it < 100 && b - a > 1e-14; ++it) {
                const double mid = 0.5 * (a + b);
                ((psi_of(v.sample(mid).q) > 0) == (pa > 0) ? a : b) = mid;
              }
              crossings.push_back(0.5 * (a + b));
            }
            return true;
          });
          BOOST_REQUIRE_MESSAGE(r.status == SimulationStatus::success, r.message);
          BOOST_TEST(r.events.empty());
          BOOST_REQUIRE_GE(crossings.size(), 5u);
          double err_T = 0.0;
          for (std::size_t i = 0; i + 2 < crossings.size(); ++i) err_T = std::max(err_T, std::abs(crossings[i + 2] - crossings[i] - T));
          BOOST_TEST_MESSAGE("ring at (" << pl.X0 << ", " << pl.Y0 << "), Omega " << Omega << ", psi0 " << psi0
                             << ": period " << crossings[2] - crossings[0] << " s (exact " << T << ", small-swing " << T0
                             << "), |period - exact| " << err_T << " s, |psi - RK4| " << err_psi << " rad, energy "
                             << err_E << " J, rolling relation " << err_slip << " m/s, gap " << err_gap << " m");
          BOOST_TEST(err_T < 1e-8);
          if (psi0 < 0.1) BOOST_TEST(std::abs(T / T0 - 1 - psi0 * psi0 / 16) < psi0 * psi0 * psi0 * psi0 / 100);
          BOOST_TEST(std::abs(crossings[0] - T / 4) < 1e-8);
          BOOST_TEST(err_psi < 1e-7);
          if (Omega == 0.0) BOOST_TEST(err_E < 2e-8 * kM * kG * L);
          BOOST_TEST(err_slip < 3e-8);
          BOOST_TEST(err_gap < 2e-8);
        }
      }
}

namespace {

// The disk set on the top of a fixed drum at th0 from the top with speed v0 (rolling), L = R + r.
struct OffDrum {
  double th0, v0;
  double L() const { return kRing + kR; }
  double b() const { return 2 * std::cos(th0) + (1 + kK) * v0 * v0 / (kG * L()); }
  // Where the rolling solution's contact force vanishes.
  double cos_lift_off() const { return b() / (3 + kK); }
  // Where its friction k sin(th) reaches mu ((3 + k) cos(th) - b): the larger root of
  // (k^2 + mu^2 a^2) c^2 - 2 mu^2 a b c + mu^2 b^2 - k^2 = 0, a = 3 + k (its first crossing).
  double cos_slip(double mu) const {
    const double a = 3 + kK, bb = b();
    return (mu * mu * a * bb + kK * std::sqrt(kK * kK + mu * mu * (a * a - bb * bb))) / (kK * kK + mu * mu * a * a);
  }
  Eigen::Vector3d q0(const Place& p) const {
    return Eigen::Vector3d(p.X0 + L() * std::sin(th0), p.Y0 + L() * std::cos(th0), 0.0);
  }
  Eigen::Vector3d qd0() const { return Eigen::Vector3d(v0 * std::cos(th0), -v0 * std::sin(th0), -v0 / kR); }
};

double cos_from_top(const Eigen::VectorXd& q, const Place& p, double L) { return (q[1] - p.Y0) / L; }

}  // namespace

// With small mu_s (0.2 and 0.05) the disk rolls off the drum until its friction reaches
// mu_s N: along the rolling phase the joint's reaction columns, in the contact frame (x along
// the tangent in the direction of travel, y the normal), are the closed form's -m g k sin(th)/(1 +
// k) and m g ((3 + k) cos(th) - b)/(1 + k) at the state's th (1e-8 of m g at rtol 1e-10; observed
// 1.8e-10 N), and the slip event comes at the closed-form cos(th_s) (1e-9; observed 2.6e-11),
// where |F_x| = mu_s F_y. With reactions = "ground" the columns are those turned by the contact
// frame (t, n) (1e-9 of m g: n here from the centre's position over the nominal R + r, off by the
// gap's relative size; observed 4.1e-12 N).
BOOST_AUTO_TEST_CASE(slip_begins_where_the_rolling_solutions_friction_reaches_mu_static) {
  const OffDrum d{0.0, 0.1};
  const double L = d.L();
  for (const Place& pl : kPlaces)
    for (double mu : {0.2, 0.05}) {
      BOOST_TEST_CONTEXT("centre (" << pl.X0 << ", " << pl.Y0 << "), mu_s " << mu) {
        auto m = model_of(body_model(false, ""), {{"X0", pl.X0}, {"Y0", pl.Y0}, {"mu_s", mu}, {"mu_k", mu}}, d.q0(pl));
        const int iF = column(*m, "F_roll_x"), iN = column(*m, "F_roll_y");
        SimulationOptions o;
        o.rtol = o.atol = 1e-10;
        Trace tr;
        const auto r = run(*m, d.q0(pl), d.qd0(), 1.0, o, {}, &tr);
        BOOST_REQUIRE_MESSAGE(r.status == SimulationStatus::success, r.message);
        BOOST_REQUIRE(!r.events.empty());
        BOOST_TEST(r.events[0].kind == ContactEventKind::slip);
        // The same run with reactions = "ground": the columns turned by the contact frame (t, n).
        std::string text = body_model(false, "");
        text.insert(text.find('\n') + 1, "reactions = \"ground\"\n");
        auto mg = model_of(text, {{"X0", pl.X0}, {"Y0", pl.Y0}, {"mu_s", mu}, {"mu_k", mu}}, d.q0(pl));
        Trace tg;
        BOOST_REQUIRE(run(*mg, d.q0(pl), d.qd0(), 1.0, o, {}, &tg).status == SimulationStatus::success);
        BOOST_REQUIRE_EQUAL(tg.t.size(), tr.t.size());
        const double ts = r.events[0].t;
        double err_F = 0.0, err_ground = 0.0;
        int n = 0;
        for (std::size_t i = 0; i < tr.t.size() && tr.t[i] < ts; ++i) {
          const double c = cos_from_top(tr.q[i], pl, L), sn = (tr.q[i][0] - pl.X0) / L;
          const double Ft = -kM * kG * kK * sn / (1 + kK), N = kM * kG * ((3 + kK) * c - d.b()) / (1 + kK);
          const double Fx = tr.derived[i][iF], Fy = tr.derived[i][iN];
          err_F = std::max({err_F, std::abs(Fx - Ft), std::abs(Fy - N)});
          // n = (sin, cos) from the centre's angle, t = (n_y, -n_x): F = Fx t + Fy n in ground.
          err_ground = std::max({err_ground, std::abs(tg.derived[i][iF] - (Fx * c + Fy * sn)),
                                 std::abs(tg.derived[i][iN] - (-Fx * sn + Fy * c))});
          ++n;
        }
        const double c_s = cos_from_top(q_at(tr, ts), pl, L);
        BOOST_TEST_MESSAGE("drum at (" << pl.X0 << ", " << pl.Y0 << "), mu_s " << mu << ": slip at cos " << c_s
                           << " (closed form " << d.cos_slip(mu) << ", diff " << c_s - d.cos_slip(mu) << "; lift-off would be " << d.cos_lift_off() << "), |F - rolling| "
                           << err_F << " N over " << n << " steps; at the switch |F_t|/N = "
                           << std::abs(r.events[0].tangential) / r.events[0].normal << "; in ground axes " << err_ground << " N");
        BOOST_TEST(n > 10);
        BOOST_TEST(err_F < 1e-8 * kM * kG);
        BOOST_TEST(err_ground < 1e-9 * kM * kG);
        BOOST_TEST(std::abs(c_s - d.cos_slip(mu)) < 1e-9);
        BOOST_TEST(std::abs(std::abs(r.events[0].tangential) - mu * r.events[0].normal) < 1e-8 * kM * kG);
      }
    }
}

// The disk released near the top of a fixed drum (from rest 0.02 rad off the top; from the top
// at 0.1 m/s) with mu_s = mu_k = 1e5. Rolling, it would lift off where N = 0, cos(th*) =
// (2 cos(th0) + (1 + k) v0^2/(g L))/(3 + k) (4/7 from rest at the very top); but its friction
// need k sin(th)/((3 + k) cos(th) - b) grows without bound there, so any finite mu lets it slip
// just before, at cos(th_s) (the quadratic above; cos(th_s) - cos(th*) = 1.2e-6 at mu = 1e5,
// 1.2e-4 at 1e3). Slipping, the friction mu_k N < what rolling needs brakes it less, so its
// centre speeds up faster and N reaches 0 sooner: it lifts off between th_s and th*. Checked: a
// slip at th_s, then the lift-off with cos(th) in [cos(th*), cos(th_s)], with zero normal force.
// Tolerance 1e-8 on cos: the integration error of the rolling phase at rtol 1e-10 (observed
// 2.5e-9; 1.5e-11 and 6e-13 at rtol 1e-11 and 1e-12).
BOOST_AUTO_TEST_CASE(disk_rolling_off_a_drum_lifts_off_at_cos_four_sevenths) {
  const double mu = 1e5;
  for (const Place& pl : kPlaces)
    for (const OffDrum& d : {OffDrum{0.02, 0.0}, OffDrum{0.0, 0.1}}) {
      BOOST_TEST_CONTEXT("centre (" << pl.X0 << ", " << pl.Y0 << "), th0 " << d.th0 << ", v0 " << d.v0) {
        auto m = model_of(body_model(false, ""), {{"X0", pl.X0}, {"Y0", pl.Y0}, {"mu_s", mu}, {"mu_k", mu}}, d.q0(pl));
        SimulationOptions o;
        o.rtol = o.atol = 1e-10;
        Trace tr;
        const auto r = run(*m, d.q0(pl), d.qd0(), 3.0, o, {}, &tr);
        BOOST_REQUIRE_MESSAGE(r.status == SimulationStatus::success, r.message);
        const auto slips = events_of(r, ContactEventKind::slip), lifts = events_of(r, ContactEventKind::lift_off);
        BOOST_REQUIRE(!slips.empty());
        BOOST_REQUIRE(!lifts.empty());
        BOOST_TEST(slips[0].t < lifts[0].t);
        const double c_s = cos_from_top(q_at(tr, slips[0].t), pl, d.L());
        const double c_l = cos_from_top(q_at(tr, lifts[0].t), pl, d.L());
        BOOST_TEST_MESSAGE("off a drum at (" << pl.X0 << ", " << pl.Y0 << "), th0 " << d.th0 << ", v0 " << d.v0
                           << ": slip at cos " << c_s << " (closed form " << d.cos_slip(mu) << ", diff "
                           << c_s - d.cos_slip(mu) << "), lift-off at t = " << lifts[0].t << " s, cos " << c_l
                           << ", rolling's cos(th*) = " << d.cos_lift_off() << " (4/7 = " << 4.0 / 7.0 << "): cos - cos(th*) = "
                           << c_l - d.cos_lift_off() << ", bracket " << c_s - d.cos_lift_off());
        BOOST_TEST(std::abs(c_s - d.cos_slip(mu)) < 1e-8);
        BOOST_TEST(c_l > d.cos_lift_off() - 1e-8);
        BOOST_TEST(c_l < c_s + 1e-8);
        BOOST_TEST(c_s - d.cos_lift_off() < 2e-6);
        BOOST_TEST(std::abs(lifts[0].normal) < 1e-8 * kM * kG);
        if (d.v0 == 0.0) BOOST_TEST(std::abs(d.cos_lift_off() - 2 * std::cos(d.th0) / 3.5) < 1e-15);
      }
    }
  BOOST_TEST(std::abs(OffDrum{0.0, 0.0}.cos_lift_off() - 4.0 / 7.0) < 1e-15);
}

// A roller on a driven drum (the drum a body turned by a driven revolute joint, motion
// A sin(w t)): outside (on top, A = 0.3 rad, w = 5 rad/s: it rolls, slips and sticks as the drum
// rocks, until it rolls off and flies) and inside (a ring rocking at A = 1.5 rad, w = 4 rad/s:
// the disk at rest at the bottom starts sliding, is dragged up, sticks, slips back ...). The
// body model's rows against the same physics written by hand in the energy form: the same
// events (kinds, 1e-8 s) and the same end state (1e-7), at the origin and at (1000, -500) m.
BOOST_AUTO_TEST_CASE(roller_on_a_driven_drum_moves_as_the_hand_written_energy_form) {
  for (const Place& pl : kPlaces)
    for (const bool inside : {false, true}) {
      BOOST_TEST_CONTEXT("centre (" << pl.X0 << ", " << pl.Y0 << "), " << (inside ? "inside" : "outside")) {
        const std::map<std::string, double> p{{"X0", pl.X0}, {"Y0", pl.Y0}, {"A", inside ? 1.5 : 0.3},
                                              {"w", inside ? 4.0 : 5.0}, {"mu_s", 0.4}, {"mu_k", 0.3}};
        const double L = inside ? kRing - kR : kRing + kR;
        const Eigen::Vector3d q0(pl.X0, pl.Y0 + (inside ? -L : L), 0.0);
        auto b = model_of(body_model(inside, "A*sin(w*t)"), p, q0);
        auto e = model_of(energy_model(inside, "A*w*cos(w*t)"), p, q0);
        SimulationOptions o;
        o.rtol = o.atol = 1e-10;
        const double T = 1.5;
        const auto rb = run(*b, q0, Eigen::Vector3d::Zero(), T, o);
        const auto re = run(*e, q0, Eigen::Vector3d::Zero(), T, o);
        BOOST_REQUIRE_MESSAGE(rb.status == SimulationStatus::success, rb.message);
        BOOST_REQUIRE_MESSAGE(re.status == SimulationStatus::success, re.message);
        std::string kinds;
        for (const auto& ev : rb.events) kinds += std::string(to_string(ev.kind)) + " ";
        BOOST_TEST_MESSAGE((inside ? "in a rocking ring" : "on a rocking drum") << " at (" << pl.X0 << ", " << pl.Y0
                           << "): events " << kinds << "; |q_end| diff " << (rb.q_end - re.q_end).cwiseAbs().maxCoeff()
                           << ", |qd_end| diff " << (rb.qd_end - re.qd_end).cwiseAbs().maxCoeff());
        BOOST_TEST(rb.events.size() >= 2u);
        BOOST_REQUIRE_EQUAL(rb.events.size(), re.events.size());
        double dt_max = 0.0;
        for (std::size_t i = 0; i < rb.events.size(); ++i) {
          BOOST_TEST(rb.events[i].kind == re.events[i].kind);
          dt_max = std::max(dt_max, std::abs(rb.events[i].t - re.events[i].t));
        }
        BOOST_TEST_MESSAGE("  event times differ by " << dt_max << " s at most");
        BOOST_TEST(dt_max < 1e-8);
        BOOST_TEST((rb.q_end - re.q_end).cwiseAbs().maxCoeff() < 1e-7);
        BOOST_TEST((rb.qd_end - re.qd_end).cwiseAbs().maxCoeff() < 1e-7);
      }
    }
}

// Restitution on a circle: a disk let fall from rest 0.1 m below the centre of a fixed ring
// (e_n = 0.5) falls h = R - r - 0.1 = 0.3 m straight down onto the bottom, where the contact's
// normal is vertical, and bounces straight up: impacts at t1 = sqrt(2 h/g), t1 + 2 e v/g,
// t1 + 2 e v/g + 2 e^2 v/g, ... with v = sqrt(2 g h), approach speeds e^k v and rebounds e^(k+1) v
// (the friction row sees no sliding: no tangential impulse, no spin). Tolerances: the flights are
// parabolas, integrated exactly; the impact times 1e-9 s and speeds 1e-8 m/s, as for the other
// contacts 1000 m out (observed 3e-14 s and 2e-13 m/s at the origin, 4.8e-11 s and 2.4e-10 m/s
// at (1000, -500) m, where the gap is resolved to ~1e-13 m and the event to its tolerance).
BOOST_AUTO_TEST_CASE(a_disk_dropped_in_a_ring_bounces_with_newtons_restitution) {
  const double e = 0.5, h = kRing - kR - 0.1, v = std::sqrt(2 * kG * h);
  for (const Place& pl : kPlaces) {
    BOOST_TEST_CONTEXT("centre (" << pl.X0 << ", " << pl.Y0 << ")") {
      const Eigen::Vector3d q0(pl.X0, pl.Y0 - 0.1, 0.0);
      auto m = contact_model("disk_ring_bodies", {{"X0", pl.X0}, {"Y0", pl.Y0}, {"e_n", e}}, q0);
      SimulationOptions o;
      o.rtol = o.atol = 1e-10;
      const auto r = run(*m, q0, Eigen::Vector3d::Zero(), 0.5 + 2 * e * v / kG + e * v / kG, o);
      BOOST_REQUIRE_MESSAGE(r.status == SimulationStatus::success, r.message);
      const auto impacts = events_of(r, ContactEventKind::impact);
      BOOST_REQUIRE_GE(impacts.size(), 3u);
      double t = std::sqrt(2 * h / kG), vk = v, err_t = 0.0, err_v = 0.0;
      for (std::size_t k = 0; k < 3; ++k) {
        err_t = std::max(err_t, std::abs(impacts[k].t - t));
        err_v = std::max({err_v, std::abs(impacts[k].vn_before + vk), std::abs(impacts[k].vn_after - e * vk)});
        t += 2 * e * vk / kG;
        vk *= e;
      }
      BOOST_TEST_MESSAGE("bouncing in a ring at (" << pl.X0 << ", " << pl.Y0 << "): impact times " << err_t
                         << " s, speeds " << err_v << " m/s off the closed form; x, spin at the end "
                         << r.q_end[0] - pl.X0 << " m, " << r.qd_end[2] << " rad/s");
      BOOST_TEST(err_t < 1e-9);
      BOOST_TEST(err_v < 1e-8);
      BOOST_TEST(std::abs(r.q_end[0] - pl.X0) < 1e-12);
      BOOST_TEST(std::abs(r.qd_end[2]) < 1e-12);
    }
  }
}
