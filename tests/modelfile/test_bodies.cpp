// Bodies, joints and forces (issue 22, docs/bodies.md): the body form expands into the energy
// form of today's model files. Oracles: the hand-written energy-form files (double pendulum,
// slider-crank), the reactions R = gᵀλ the engine computes (a formula of R, not of λ), statics
// in closed form, and the expanded text read back (bit-identical).
#define BOOST_TEST_MODULE test_bodies
#include <boost/test/unit_test.hpp>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <random>
#include <sstream>
#include <string>

#include "mech/dynamics.hpp"
#include "mech/simulation.hpp"
#include "modelfile/bodies.hpp"
#include "modelfile/expression_model.hpp"
#include "modelfile/model_file.hpp"
#include "modelfile/model_source.hpp"
#include "modelfile_test_util.hpp"

#include "mech/contacts/switching.hpp"  // the contact joints' test

using namespace pcsim;
using namespace pcsim::modelfile;
using namespace pcsim::modelfile::testing;

namespace {

std::vector<int> all_constraints(const mech::Model& m) {
  std::vector<int> a;
  for (int i = 0; i < static_cast<int>(m.constraints().size()); ++i) a.push_back(i);
  return a;
}

// M, h, Q, g, g0, γ of two models at `count` random states (coordinates also far from the
// origin: offset), every constraint of `a` active, to 1e-12 of each block's scale.
void expect_same_equations(const mech::Model& a, const mech::Model& b, int count, double offset) {
  BOOST_REQUIRE_EQUAL(a.n(), b.n());
  BOOST_REQUIRE_EQUAL(a.constraints().size(), b.constraints().size());
  for (std::size_t i = 0; i < a.constraints().size(); ++i)
    BOOST_CHECK_EQUAL(a.constraints()[i].name, b.constraints()[i].name);
  std::mt19937 rng(22);
  const std::vector<int> active = all_constraints(a);
  double worst = 0.0;
  for (int k = 0; k < count; ++k) {
    Eigen::VectorXd q(a.n()), qd(a.n());
    for (int i = 0; i < a.n(); ++i) {
      q[i] = (k % 2 ? offset : 0.0) + 3.0 * uniform(rng);
      qd[i] = 5.0 * uniform(rng);
    }
    const double t = uniform(rng);
    const Evaluation ea = evaluate(a, active, t, q, qd), eb = evaluate(b, active, t, q, qd);
    for (double d : {rel_diff(ea.M, eb.M), rel_diff(ea.h, eb.h, 1e-12), rel_diff(ea.Q, eb.Q, 1e-12),
                     rel_diff(ea.g, eb.g), rel_diff(ea.g0, eb.g0, 1e-12),
                     rel_diff(ea.gamma, eb.gamma, 1e-12)})
      worst = std::max(worst, d);
  }
  BOOST_TEST_MESSAGE("worst relative difference " << worst);
  BOOST_CHECK_LT(worst, 1e-12);
}

std::shared_ptr<const ModelDescription> expanded(const std::string& file) {
  const auto src = detail::load_model_source(model_path(file));
  return load_model_text(bodies::energy_form_text(src), "expanded_" + file);
}

}  // namespace

BOOST_AUTO_TEST_CASE(double_pendulum_as_bodies_equals_the_energy_form_file) {
  const auto bodies = load_model_file(model_path("double_pendulum_bodies.toml"));
  const auto energy = load_model_file(model_path("double_pendulum.toml"));
  BOOST_CHECK(bodies->coordinates() == energy->coordinates());
  expect_same_equations(*bodies->instantiate({}), *energy->instantiate({}), 500, 1000.0);
  expect_same_equations(*bodies->instantiate({{"m2", 2.5}, {"L1", 0.3}}),
                        *energy->instantiate({{"m2", 2.5}, {"L1", 0.3}}), 100, 0.0);
}

BOOST_AUTO_TEST_CASE(slider_crank_as_bodies_equals_the_energy_form_file) {
  const auto bodies = load_model_file(model_path("slider_crank_bodies.toml"));
  const auto energy = load_model_file(model_path("slider_crank.toml"));
  BOOST_CHECK(bodies->coordinates() == energy->coordinates());
  expect_same_equations(*bodies->instantiate({}), *energy->instantiate({}), 500, 1000.0);
  expect_same_equations(*bodies->instantiate({{"l1", 0.35}, {"tau", -2.0}, {"c", 3.0}}),
                        *energy->instantiate({{"l1", 0.35}, {"tau", -2.0}, {"c", 3.0}}), 100, 0.0);
}

BOOST_AUTO_TEST_CASE(expanded_text_reads_back_to_bit_identical_equations_and_outputs) {
  for (const std::string file : {"double_pendulum_bodies.toml", "slider_crank_bodies.toml", "contact/disk_ring_bodies.toml"}) {
    const auto a = load_model_file(model_path(file))->instantiate({});
    const auto b = expanded(file)->instantiate({});
    const std::vector<int> active = all_constraints(*a);
    std::mt19937 rng(7);
    for (int k = 0; k < 100; ++k) {
      Eigen::VectorXd q(a->n()), qd(a->n()), qdd(a->n()), R(a->n());
      for (int i = 0; i < a->n(); ++i) {
        q[i] = 2.0 * uniform(rng);
        qd[i] = uniform(rng);
        qdd[i] = uniform(rng);
        R[i] = uniform(rng);
      }
      Eigen::VectorXd lambda(static_cast<Eigen::Index>(active.size()));
      for (auto& l : lambda) l = uniform(rng);
      const Evaluation ea = evaluate(*a, active, 0.1, q, qd), eb = evaluate(*b, active, 0.1, q, qd);
      BOOST_CHECK(ea.M == eb.M);
      BOOST_CHECK(ea.h == eb.h);
      BOOST_CHECK(ea.Q == eb.Q);
      BOOST_CHECK(ea.g == eb.g);
      BOOST_CHECK(ea.g0 == eb.g0);
      BOOST_CHECK(ea.gamma == eb.gamma);
      Eigen::VectorXd oa, ob;
      a->derived_with_multipliers(0.1, q, qd, qdd, R, active, lambda, oa);
      b->derived_with_multipliers(0.1, q, qd, qdd, R, active, lambda, ob);
      BOOST_REQUIRE_EQUAL(oa.size(), ob.size());
      for (Eigen::Index i = 0; i < oa.size(); ++i)
        BOOST_CHECK(oa[i] == ob[i] || (std::isnan(oa[i]) && std::isnan(ob[i])));
    }
    BOOST_CHECK(a->derived_names() == b->derived_names());
  }
}

// `pcsim expand` of a body model whose joints carry contact attributes (issue 22 with issue 12's):
// the printed rows carry them (unilateral, restitution, friction, mu_static, mu_kinetic), the
// expanded file gives the same contact data, and a switching run of it is the body model's, bit
// for bit: the disk spun backwards on its rolling joint (one stick), the ball on its point_on_line
// joint (impacts, accumulation), the frictionless and the rolling coin (rough rows).
BOOST_AUTO_TEST_CASE(expanded_contact_joints_carry_their_attributes_and_switch_as_the_body_model) {
  struct Case {
    std::string file;
    std::vector<std::string> printed;
    Eigen::VectorXd q0, qd0;
  };
  const std::vector<Case> cases{
      {"contact/disk_incline_bodies.toml",
       {"name = \"road_contact\"\n", "unilateral = true\nrestitution = \"e_n\"\n",
        "friction = \"road_contact\"\nmu_static = \"mu_s\"\nmu_kinetic = \"mu_k\"\n"},
       Eigen::Vector3d(0.2 * std::sin(0.5), 0.2 * std::cos(0.5), 0.0), Eigen::Vector3d(0.0, 0.0, -10.0)},
      {"contact/bouncing_ball_bodies.toml",
       {"name = \"floor\"\nholonomic = \"ball_y - Y0\"\nunilateral = true\nrestitution = \"e_n\"\n"},
       Eigen::Vector2d(0.0, 1.0), Eigen::Vector2d(0.1, 0.0)},
      // The disk in a ring (a rolling joint on a circle, inside): set 0.5 rad up the ring's side
      // spinning at 20 rad/s, it slides and sticks.
      {"contact/disk_ring_bodies.toml",
       {"name = \"mill_contact\"\nholonomic = \"R - r - mill_dist\"\nunilateral = true\nrestitution = \"e_n\"\n",
        "friction = \"mill_contact\"\nmu_static = \"mu_s\"\nmu_kinetic = \"mu_k\"\n"},
       Eigen::Vector3d(0.4 * std::sin(0.5), 0.4 - 0.4 * std::cos(0.5), 0.0), Eigen::Vector3d(0.0, 0.0, 20.0)},
      // The frictionless spatial wheel (issue 22): an upright coin dropped 1.5 m, spinning at
      // 20 rad/s (impacts until 1.5 s, before its accumulation at 1.66 s).
      {"contact/coin_bodies.toml",
       {"name = \"bounce_n\"\nholonomic = \"coin_z - Z0 - r*bounce_sigma\"\nunilateral = true\nrestitution = \"e_n\"\n"},
       (Eigen::VectorXd(7) << 0.0, 0.0, 1.512, std::sqrt(0.5), std::sqrt(0.5), 0.0, 0.0).finished(),
       (Eigen::VectorXd(7) << 0.1, 0.0, 0.0, 0.0, 0.0, -10 * std::sqrt(0.5), 10 * std::sqrt(0.5)).finished()},
      // The rolling spatial wheel, unilateral (issue 22): its no-slip rows printed as rough rows;
      // dropped 0.1 m moving at 0.4 m/s and turning at 10 rad/s about ground y (a rough landing).
      {"contact/coin_rolling_bodies.toml",
       {"name = \"bounce_n\"\nholonomic = \"coin_z - Z0 - r*bounce_sigma\"\nunilateral = true\nrestitution = \"e_n\"\n",
        "friction = \"bounce_n\"\nrough = true\n"},
       (Eigen::VectorXd(7) << 0.0, 0.0, 0.112, std::sqrt(0.5), std::sqrt(0.5), 0.0, 0.0).finished(),
       (Eigen::VectorXd(7) << 0.4, 0.0, 0.0, 0.0, 0.0, 5 * std::sqrt(0.5), -5 * std::sqrt(0.5)).finished()}};
  for (const Case& c : cases) {
    BOOST_TEST_CONTEXT(c.file) {
      const auto src = detail::load_model_source(model_path(c.file));
      const std::string text = bodies::energy_form_text(src);
      for (const auto& p : c.printed) BOOST_TEST(text.find(p) != std::string::npos, "printed: " << p);
      const auto a = load_model_file(model_path(c.file))->instantiate({}, c.q0, 0.0);
      const auto b = load_model_text(text, "expanded.toml")->instantiate({}, c.q0, 0.0);
      BOOST_REQUIRE_EQUAL(a->constraints().size(), b->constraints().size());
      int contacts = 0;
      for (std::size_t i = 0; i < a->constraints().size(); ++i) {
        const mech::ContactInfo &ca = a->constraints()[i].contact, &cb = b->constraints()[i].contact;
        BOOST_TEST(a->constraints()[i].name == b->constraints()[i].name);
        BOOST_TEST(ca.unilateral == cb.unilateral);
        BOOST_TEST(ca.restitution == cb.restitution);
        BOOST_TEST(ca.friction_of == cb.friction_of);
        BOOST_TEST(ca.rough == cb.rough);
        BOOST_TEST(ca.mu_static == cb.mu_static);
        BOOST_TEST(ca.mu_kinetic == cb.mu_kinetic);
        contacts += ca.unilateral ? 1 : 0;
      }
      BOOST_TEST(contacts == 1);
      mech::SimulationOptions o;
      o.t_end = 1.5;
      o.rtol = o.atol = 1e-10;
      for (const auto& ci : a->constraints()) o.active_constraints.push_back(ci.name);
      mech::SwitchingOptions sw;
      sw.zeno_time = 1e-9;
      const auto ra = mech::simulate_switching(*a, c.q0, c.qd0, o, sw);
      const auto rb = mech::simulate_switching(*b, c.q0, c.qd0, o, sw);
      BOOST_REQUIRE_MESSAGE(ra.status == mech::SimulationStatus::success, ra.message);
      BOOST_REQUIRE_MESSAGE(rb.status == mech::SimulationStatus::success, rb.message);
      BOOST_TEST(!ra.events.empty());
      BOOST_REQUIRE_EQUAL(ra.events.size(), rb.events.size());
      for (std::size_t i = 0; i < ra.events.size(); ++i) {
        BOOST_TEST(ra.events[i].kind == rb.events[i].kind);
        BOOST_TEST(ra.events[i].t == rb.events[i].t);
      }
      BOOST_TEST(ra.q_end == rb.q_end);
      BOOST_TEST(ra.qd_end == rb.qd_end);
    }
  }
}

// A rolling joint on a circle (docs/bodies.md "Rolling on a circle") on a FREE body1 (a drum with
// its own coordinates, the circle's centre `hub` off its origin, the wheel's centre marker off
// the disk's), outside and inside, the disk absolute or placed on the drum by a planar tree
// joint (s, u, phi), at random states near contact, at the origin and 1000 m out: the row
// roll_contact is the gap |d| - (R + r) (inside (R - r) - |d|), d = c - o; the row roll_rolling's
// g q_d + g0 is the sliding velocity t.(v_wheel(P) - v_drum(P)) at P = c - r n, n = +-d/|d|,
// t = (n_y, -n_x), computed here from the rigid-body velocities; the reaction columns from
// random multipliers are (lambda_rolling, lambda_contact, r lambda_rolling) in the contact frame
// and lambda_rolling t + lambda_contact n in ground axes. Bounds 1e-12 (relative to |v|, |lambda|;
// the gap in m): rounding of coordinates 1000 m out (observed 2.6e-13 m, 2.7e-13, 2.8e-13).
BOOST_AUTO_TEST_CASE(rolling_on_a_circle_rows_are_the_gap_and_the_contact_points_sliding_velocity) {
  const double R = 0.7, r = 0.1;
  const Eigen::Vector2d hub(0.3, -0.2), cm(0.02, 0.01);
  auto rot = [](double a) { return (Eigen::Matrix2d() << std::cos(a), -std::sin(a), std::sin(a), std::cos(a)).finished(); };
  auto perp = [](const Eigen::Vector2d& v) { return Eigen::Vector2d(-v[1], v[0]); };  // z x v
  for (const bool tree : {false, true})
    for (const bool inside : {false, true})
      for (const char* reactions : {"joint", "ground"}) {
        BOOST_TEST_CONTEXT((tree ? "tree" : "absolute") << ", " << (inside ? "inside" : "outside") << ", reactions = " << reactions) {
          const std::string text = std::string("[model]\nname = \"m\"\nreactions = \"") + reactions + "\"\n"
              "[model.body.drum]\nmass = 5\ninertia = 1\nmarkers = { hub = [0.3, -0.2] }\n"
              "[model.body.disk]\nmass = 1\ninertia = 0.005\nmarkers = { c = [0.02, 0.01] }\n" +
              (tree ? "[model.joint.place]\ntype = \"planar\"\nbody1 = \"drum\"\nbody2 = \"disk\"\ncoordinates = [\"s\", \"u\", \"phi\"]\n" : "") +
              "[model.joint.roll]\ntype = \"rolling\"\nbody1 = \"drum\"\nmarker1 = \"hub\"\nbody2 = \"disk\"\nmarker2 = \"c\"\n"
              "radius = 0.1\nsurface = \"circle\"\ncircle_radius = 0.7\ninside = " + (inside ? "true" : "false") + "\n";
          const auto m = load_model_text(text, "m.toml")->instantiate({});
          BOOST_REQUIRE(m->coordinates() == (tree ? std::vector<std::string>{"drum_x", "drum_y", "drum_th", "s", "u", "phi"}
                                                  : std::vector<std::string>{"drum_x", "drum_y", "drum_th", "disk_x", "disk_y", "disk_th"}));
          const int ic = m->constraint_index("roll_contact"), ir = m->constraint_index("roll_rolling");
          const std::vector<int> active = all_constraints(*m);
          std::mt19937 rng(inside ? 61 : 62);
          double worst_gap = 0, worst_rate = 0, worst_F = 0;
          for (int k = 0; k < 40; ++k) {
            Eigen::VectorXd q(6), qd(6);
            const double off = k % 2 ? 1000.0 : 0.0;
            q.head<3>() << off + uniform(rng), -off + uniform(rng), 3 * uniform(rng);
            for (auto& v : qd) v = 2 * uniform(rng);
            const Eigen::Vector2d r1 = q.head<2>(), o = r1 + rot(q[2]) * hub;
            const double psi = 3 * uniform(rng), rho = (inside ? R - r : R + r) + 1e-3 * uniform(rng);
            const Eigen::Vector2d c = o + rho * Eigen::Vector2d(std::cos(psi), std::sin(psi));
            // The disk's angle th2, its rate w2, its centre marker's velocity, from the coordinates.
            double th2, w2;
            Eigen::Vector2d vc;
            if (tree) {
              q[5] = 3 * uniform(rng);
              th2 = q[2] + q[5];
              w2 = qd[2] + qd[5];
              q.segment<2>(3) = rot(q[2]).transpose() * (c - r1 - rot(th2) * cm);
              vc = qd.head<2>() + qd[2] * perp(rot(q[2]) * q.segment<2>(3)) + rot(q[2]) * qd.segment<2>(3) +
                   w2 * perp(rot(th2) * cm);
            } else {
              th2 = q[5] = 3 * uniform(rng);
              w2 = qd[5];
              q.segment<2>(3) = c - rot(th2) * cm;
              vc = qd.segment<2>(3) + w2 * perp(rot(th2) * cm);
            }
            const Eigen::Vector2d d = c - o;
            const Eigen::Vector2d n = (inside ? -1.0 : 1.0) * d / d.norm(), t(n[1], -n[0]), P = c - r * n;
            const Eigen::Vector2d v_wheel = vc + w2 * perp(P - c), v_drum = qd.head<2>() + qd[2] * perp(P - r1);
            const double gap = inside ? R - r - d.norm() : d.norm() - (R + r);
            worst_gap = std::max(worst_gap, std::abs(m->position_residual(ic, 0.0, q) - gap));
            const Evaluation e = evaluate(*m, active, 0.0, q, qd);
            const auto row = std::find(active.begin(), active.end(), ir) - active.begin();
            const double rate = e.g.row(row).dot(qd) + e.g0[row];
            worst_rate = std::max(worst_rate, std::abs(rate - t.dot(v_wheel - v_drum)) / (v_wheel.norm() + v_drum.norm()));
            Eigen::VectorXd lambda(static_cast<Eigen::Index>(active.size())), out;
            for (auto& l : lambda) l = 10.0 * uniform(rng);
            const Eigen::VectorXd zero = Eigen::VectorXd::Zero(6);
            m->derived_with_multipliers(0.0, q, qd, zero, zero, active, lambda, out);
            auto column = [&](const std::string& name) { return out[name_index(m->derived_names(), name)]; };
            const double lc = lambda[std::find(active.begin(), active.end(), ic) - active.begin()], lr = lambda[row];
            const Eigen::Vector2d F = std::string(reactions) == "joint" ? Eigen::Vector2d(lr, lc) : Eigen::Vector2d(lr * t + lc * n);
            worst_F = std::max({worst_F, std::abs(column("F_roll_x") - F[0]) / 10.0, std::abs(column("F_roll_y") - F[1]) / 10.0,
                                std::abs(column("M_roll_z") - r * lr) / 10.0});
          }
          BOOST_TEST_MESSAGE("circle, " << (tree ? "tree" : "absolute") << ", " << (inside ? "inside" : "outside")
                             << ", reactions = " << reactions << ": gap " << worst_gap << " m, sliding velocity "
                             << worst_rate << " of |v|, reactions " << worst_F << " of |lambda|");
          BOOST_TEST(worst_gap < 1e-12);
          BOOST_TEST(worst_rate < 1e-12);
          BOOST_TEST(worst_F < 1e-12);
        }
      }
}

// `pcsim expand` of the 2-D Coulomb cone's joints (issue 22): the point_on_plane of
// models/contact/puck_plane_bodies.toml (rows table_slide_x, table_slide_y) and the rolling wheel
// of models/contact/coin_friction_bodies.toml (rows bounce_x, bounce_y) print BOTH friction rows
// with friction = the gap row and the joint's mu_static, mu_kinetic; the expanded text loads,
// carries the same contact data, and gives bit for bit the same M, h, Q, g, g0, gamma and outputs
// (with multipliers) at 50 random states. No switching run here: the engine's cone is tested
// with the engine (tests/mech/contacts).
BOOST_AUTO_TEST_CASE(expanded_coulomb_cone_joints_print_both_friction_rows_and_read_back_bit_for_bit) {
  struct Case {
    std::string file, gap, x, y;
  };
  for (const Case& c : {Case{"contact/puck_plane_bodies.toml", "table_z", "table_slide_x", "table_slide_y"},
                        Case{"contact/coin_friction_bodies.toml", "bounce_n", "bounce_x", "bounce_y"}}) {
    BOOST_TEST_CONTEXT(c.file) {
      const std::string text = bodies::energy_form_text(detail::load_model_source(model_path(c.file)));
      for (const std::string& row : {c.x, c.y}) {
        const std::string head = "name = \"" + row + "\"\nvelocity = {";
        const auto at = text.find(head);
        BOOST_REQUIRE_MESSAGE(at != std::string::npos, "printed: " << row);
        const auto end = text.find("\n\n", at);
        const std::string block = text.substr(at, end - at);
        BOOST_TEST(block.find("\nfriction = \"" + c.gap + "\"\nmu_static = \"mu_s\"\nmu_kinetic = \"mu_k\"") !=
                       std::string::npos, block);
        BOOST_TEST(block.find("rough") == std::string::npos, block);
      }
      const auto da = load_model_file(model_path(c.file));
      const auto db = load_model_text(text, "expanded.toml");
      const auto a = da->instantiate({}), b = db->instantiate({});
      BOOST_REQUIRE_EQUAL(a->constraints().size(), b->constraints().size());
      for (std::size_t i = 0; i < a->constraints().size(); ++i) {
        const mech::ContactInfo &ca = a->constraints()[i].contact, &cb = b->constraints()[i].contact;
        BOOST_TEST(a->constraints()[i].name == b->constraints()[i].name);
        BOOST_TEST(static_cast<int>(a->constraints()[i].kind) == static_cast<int>(b->constraints()[i].kind));
        BOOST_TEST(ca.unilateral == cb.unilateral);
        BOOST_TEST(ca.restitution == cb.restitution);
        BOOST_TEST(ca.friction_of == cb.friction_of);
        BOOST_TEST(ca.rough == cb.rough);
        BOOST_TEST(ca.mu_static == cb.mu_static);
        BOOST_TEST(ca.mu_kinetic == cb.mu_kinetic);
      }
      const int gap = b->constraint_index(c.gap);
      for (const std::string& row : {c.x, c.y}) {
        const mech::ContactInfo& cb = b->constraints()[b->constraint_index(row)].contact;
        BOOST_TEST((cb.is_coulomb() && cb.friction_of == gap), row);
      }
      const std::vector<int> active = all_constraints(*a);
      std::mt19937 rng(17);
      for (int k = 0; k < 50; ++k) {
        Eigen::VectorXd q(a->n()), qd(a->n()), qdd(a->n()), R(a->n());
        for (int i = 0; i < a->n(); ++i) {
          q[i] = (k % 2 ? 1000.0 : 0.0) + uniform(rng);
          qd[i] = uniform(rng);
          qdd[i] = uniform(rng);
          R[i] = uniform(rng);
        }
        Eigen::VectorXd lambda(static_cast<Eigen::Index>(active.size()));
        for (auto& l : lambda) l = uniform(rng);
        const Evaluation ea = evaluate(*a, active, 0.1, q, qd), eb = evaluate(*b, active, 0.1, q, qd);
        BOOST_CHECK(ea.M == eb.M);
        BOOST_CHECK(ea.h == eb.h);
        BOOST_CHECK(ea.Q == eb.Q);
        BOOST_CHECK(ea.g == eb.g);
        BOOST_CHECK(ea.g0 == eb.g0);
        BOOST_CHECK(ea.gamma == eb.gamma);
        Eigen::VectorXd oa, ob;
        a->derived_with_multipliers(0.1, q, qd, qdd, R, active, lambda, oa);
        b->derived_with_multipliers(0.1, q, qd, qdd, R, active, lambda, ob);
        BOOST_REQUIRE_EQUAL(oa.size(), ob.size());
        for (Eigen::Index i = 0; i < oa.size(); ++i)
          BOOST_CHECK(oa[i] == ob[i] || (std::isnan(oa[i]) && std::isnan(ob[i])));
      }
      BOOST_CHECK(a->derived_names() == b->derived_names());
    }
  }
}

// The multipliers in outputs: the body model's rod tensions come from lambda (F_rod_x = 2λ|d|),
// the energy-form file's from R (a projection of the generalized reactions on the rods); over a
// chaotic run they agree at every output time.
BOOST_AUTO_TEST_CASE(lambda_outputs_equal_the_reactions_projected_on_the_rods) {
  const auto desc = load_model_file(model_path("double_pendulum_bodies.toml"));
  const auto model = desc->instantiate({});
  Eigen::VectorXd q0(4), qd0 = Eigen::VectorXd::Zero(4);
  q0 << 0.8660254037844386, -0.5, 1.5660254037844386, -0.5;
  mech::SimulationOptions o;
  o.t_end = 1.0;
  o.rtol = 1e-9;
  o.atol = 1e-11;
  o.active_constraints = desc->default_active_constraints();
  const auto names = model->derived_names();
  const auto col = [&](const std::string& n) {
    return static_cast<int>(std::find(names.begin(), names.end(), n) - names.begin());
  };
  int checked = 0;
  double worst = 0.0;
  const auto r = mech::simulate(*model, q0, qd0, o, [&](const mech::StepView& v) {
    const mech::Sample& s = v.sample(v.t);
    const Eigen::VectorXd& q = s.q;
    const double d1 = std::hypot(q[0], q[1]), d2 = std::hypot(q[2] - q[0], q[3] - q[1]);
    // From R: the lower rod's tension from bob2's reaction; the upper one's from bob1's
    // reaction minus the lower rod's pull on bob1 (as models/double_pendulum.toml writes it).
    const double t2 = -(s.R[2] * (q[2] - q[0]) + s.R[3] * (q[3] - q[1])) / d2;
    const double t1 = -(s.R[0] * q[0] + s.R[1] * q[1]) / d1 +
                      t2 * ((q[2] - q[0]) * q[0] + (q[3] - q[1]) * q[1]) / (d1 * d2);
    const double scale = 1.0 + std::abs(t1) + std::abs(t2);
    worst = std::max({worst, std::abs(s.derived[col("tension1")] - t1) / scale,
                      std::abs(s.derived[col("tension2")] - t2) / scale});
    ++checked;
    return true;
  });
  BOOST_REQUIRE(r.status == mech::SimulationStatus::success);
  BOOST_CHECK_GT(checked, 20);
  BOOST_TEST_MESSAGE("worst relative difference " << worst);
  BOOST_CHECK_LT(worst, 1e-9);
}

// A body hanging at rest from a revolute joint whose frame (marker1 on ground) is turned by a:
// the joint pulls the body up with m g, i.e. F = (m g sin a, m g cos a) in the joint frame, and
// no moment about the pin. In ground axes (reactions = "ground"): (0, m g).
BOOST_AUTO_TEST_CASE(joint_reaction_is_reported_in_the_joint_frame_and_in_ground) {
  for (const std::string frame : {"joint", "ground"}) {
    const std::string text = R"([model]
name = "hanging"
reactions = ")" + frame + R"("
[model.parameters]
m = 2.0
L = 0.7
a = 0.5
[model.body.ground]
markers = { pin = { at = [1000, -2000], angle = "a" } }
[model.body.link]
mass = "m"
inertia = "m*L^2/12"
com = [0, "-L/2"]
markers = { top = [0, 0] }
[model.joint.pin]
type = "revolute"
marker1 = "pin"
body2 = "link"
marker2 = "top"
[model.force.gravity]
type = "gravity"
g = [0, -9.81]
)";
    const auto desc = load_model_text(text, "hanging.toml");
    const auto model = desc->instantiate({});
    BOOST_REQUIRE(model->coordinates() == (std::vector<std::string>{"link_x", "link_y", "link_th"}));
    Eigen::VectorXd q0(3), qd0 = Eigen::VectorXd::Zero(3);
    q0 << 1000.0, -2000.0, 0.0;
    mech::SimulationOptions o;
    o.t_end = 0.01;
    o.active_constraints = desc->default_active_constraints();
    const auto names = model->derived_names();
    BOOST_REQUIRE(names == (std::vector<std::string>{"F_pin_x", "F_pin_y", "M_pin_z"}));
    Eigen::VectorXd first;
    mech::simulate(*model, q0, qd0, o, [&](const mech::StepView& v) {
      if (first.size() == 0) first = v.sample(v.t).derived;
      return true;
    });
    BOOST_REQUIRE_EQUAL(first.size(), 3);
    const double mg = 2.0 * 9.81, a = 0.5;
    if (frame == "joint") {
      BOOST_CHECK_CLOSE(first[0], mg * std::sin(a), 1e-8);
      BOOST_CHECK_CLOSE(first[1], mg * std::cos(a), 1e-8);
    } else {
      BOOST_CHECK_SMALL(first[0], 1e-9 * mg);
      BOOST_CHECK_CLOSE(first[1], mg, 1e-8);
    }
    BOOST_CHECK_EQUAL(first[2], 0.0);
  }
}

// The sieve as bodies and joints (models/sieve_1995_bodies.toml) against the paper's (3.4),
// (3.4a)-(3.4f) with the errata applied (models/sieve_1995.toml): M, h (so T up to terms that
// do not enter the equations of motion), Q and every constraint row at 1,000 random states.
BOOST_AUTO_TEST_CASE(sieve_as_bodies_equals_the_errata_corrected_energy_form) {
  const auto bodies = load_model_file(model_path("sieve_1995_bodies.toml"));
  const auto energy = load_model_file(model_path("sieve_1995.toml"));
  BOOST_CHECK(bodies->coordinates() == energy->coordinates());
  Eigen::VectorXd q0(6);
  q0 << 0.0, 0.0, 0.0, 0.4, 0.15, 0.0;
  expect_same_equations(*bodies->instantiate({}, q0), *energy->instantiate({}, q0), 1000, 0.0);
  // Other geometry (every attachment point off its default) and a state far from the origin.
  const std::map<std::string, double> p{{"yc", 0.07}, {"yb", -0.05}, {"xc", 0.03}, {"xb", -0.02},
                                        {"x0", -0.3}, {"y0", 0.45}, {"e", 0.02}, {"u0", 0.2}};
  expect_same_equations(*bodies->instantiate(p, q0), *energy->instantiate(p, q0), 200, 10.0);
}

// [model] velocity_terms: h as derived from T as written, or expanded in the velocities with like
// terms combined (the default with bodies and joints). Both are the same equations: M, h, Q and
// every row agree to 1e-12 of each block's scale at 300 random states (half of them with every
// coordinate 1000 away from the origin), for energy-form files and body models alike; and the
// expansion is what makes the sieve as bodies no longer than the paper's form on the tape.
BOOST_AUTO_TEST_CASE(velocity_terms_expanded_and_as_written_are_the_same_equations) {
  auto with = [](const std::string& file, const char* value) {
    std::ifstream in(model_path(file));
    std::stringstream buffer;
    buffer << in.rdbuf();
    std::string text = buffer.str();
    const auto at = text.find("[model]\n");
    BOOST_REQUIRE(at != std::string::npos);
    text.insert(at + 8, std::string("velocity_terms = \"") + value + "\"\n");
    return load_model_text(text, file);
  };
  auto kinetic = [](const ModelDescription& d) {
    return d.compiled().tape.blocks[d.compiled().kinetic_block].code.size();
  };
  for (const char* file : {"sieve_1995.toml", "double_pendulum_minimal.toml", "rolling_coin.toml",
                           "tumbling_body.toml", "flyball_governor.toml", "top_heavy.toml", "sieve_1995_bodies.toml",
                           "double_pendulum_bodies.toml", "top_heavy_bodies.toml", "whipple_bodies.toml",
                           "slider_crank_spatial.toml"}) {
    BOOST_TEST_CONTEXT(file) {
      const auto written = with(file, "as_written"), expanded = with(file, "expanded");
      const auto by_default = load_model_file(model_path(file));
      // The default: as written for an energy-form file, expanded with bodies (the same tape).
      std::ifstream in(model_path(file));
      std::stringstream buffer;
      buffer << in.rdbuf();
      const bool body_form = buffer.str().find("[model.body") != std::string::npos;
      BOOST_TEST(kinetic(*by_default) == kinetic(body_form ? *expanded : *written));
      // A row is expanded only where its expression comes out smaller by a fifth; the tape then
      // is shorter but for the rare row whose sharing differs (the Whipple bicycle: 3527 against
      // 3516 instructions, +0.3 %).
      BOOST_TEST(kinetic(*expanded) <= 1.01 * kinetic(*written));
      BOOST_TEST_MESSAGE(file << ": kinetic block " << kinetic(*written) << " as written, " << kinetic(*expanded)
                              << " expanded");
      const Eigen::VectorXd q0 = Eigen::VectorXd::Constant(static_cast<int>(written->coordinates().size()), 0.1);
      expect_same_equations(*expanded->instantiate({}, q0), *written->instantiate({}, q0), 300, 1000.0);
    }
  }
  const auto sieve = with("sieve_1995.toml", "as_written");
  const auto sieve_bodies = load_model_file(model_path("sieve_1995_bodies.toml"));
  BOOST_TEST(kinetic(*sieve_bodies) < kinetic(*sieve));
  BOOST_TEST(kinetic(*with("sieve_1995.toml", "expanded")) < kinetic(*sieve));
}

// The two sieves integrate to the same motion (rtol 1e-10): the states and the reactions agree
// at every output time to 1e-7 of their scale over 1 s (45 excitation periods).
BOOST_AUTO_TEST_CASE(sieve_as_bodies_runs_as_the_energy_form) {
  const auto da = load_model_file(model_path("sieve_1995_bodies.toml"));
  const auto db = load_model_file(model_path("sieve_1995.toml"));
  Eigen::VectorXd q0(6), qd0 = Eigen::VectorXd::Zero(6);
  q0 << 0.0, 0.0, 0.0, 0.4, 0.15, 0.0;
  const auto ma = da->instantiate({}, q0), mb = db->instantiate({}, q0);
  mech::SimulationOptions o;
  o.t_end = 1.0;
  o.rtol = 1e-10;
  o.atol = 1e-13;
  o.active_constraints = {"contact", "rolling"};
  std::vector<mech::Sample> sa, sb;
  auto record = [](std::vector<mech::Sample>& out) {
    return [&out](const mech::StepView& v) {
      out.push_back(v.sample(v.t));
      return true;
    };
  };
  const auto ra = mech::simulate(*ma, q0, qd0, o, record(sa));
  const auto rb = mech::simulate(*mb, q0, qd0, o, record(sb));
  BOOST_REQUIRE(ra.status == mech::SimulationStatus::success);
  BOOST_REQUIRE(rb.status == mech::SimulationStatus::success);
  const double dq = rel_diff(ra.q_end.head(3), rb.q_end.head(3), 1e-9);
  const double dv = rel_diff(ra.qd_end, rb.qd_end, 1e-9);
  BOOST_TEST_MESSAGE("q_end (desk) " << dq << ", qd_end " << dv);
  BOOST_CHECK_LT(dq, 1e-6);
  BOOST_CHECK_LT(dv, 1e-6);
  BOOST_CHECK_LT(std::abs(ra.q_end[3] - rb.q_end[3]), 1e-10);
  // The normal reaction: R_u ~ m2 g cos(theta), the one that decides contact.
  BOOST_REQUIRE(!sa.empty() && !sb.empty());
  BOOST_CHECK_CLOSE(sa.back().R[4], sb.back().R[4], 1e-5);
}

namespace {

// θ'' = −k cos θ (θ from the horizontal), classical RK4 with step h: the minimal-coordinate
// solution the body models are checked against (an independent formulation).
double pendulum_angle(double k, double theta0, double t_end, double h = 1e-4) {
  double th = theta0, w = 0.0;
  const int steps = static_cast<int>(std::lround(t_end / h));
  auto f = [k](double a) { return -k * std::cos(a); };
  for (int i = 0; i < steps; ++i) {
    const double k1t = w, k1w = f(th);
    const double k2t = w + 0.5 * h * k1w, k2w = f(th + 0.5 * h * k1t);
    const double k3t = w + 0.5 * h * k2w, k3w = f(th + 0.5 * h * k2t);
    const double k4t = w + h * k3w, k4w = f(th + h * k3t);
    th += h / 6.0 * (k1t + 2 * k2t + 2 * k3t + k4t);
    w += h / 6.0 * (k1w + 2 * k2w + 2 * k3w + k4w);
  }
  return th;
}

}  // namespace

// IFToMM A01, the simple pendulum (m = 1 kg, L = 1 m, g = 9.81, released horizontally): a
// particle on a rod (a distance joint, 2 coordinates) and, as a physical pendulum, a uniform
// bar on a revolute joint (3 coordinates, 2 rows), each against the minimal-coordinate angle
// integrated by RK4 in this test; energy balance over 5 s.
BOOST_AUTO_TEST_CASE(iftomm_a01_pendulum_follows_the_minimal_coordinate_solution) {
  const double g = 9.81, L = 1.0, t_end = 5.0;
  struct Variant {
    std::string text;
    Eigen::VectorXd q0;
    double k;  // θ'' = −k cos θ
  };
  std::vector<Variant> variants;
  {
    Variant v;
    v.text = R"([model]
name = "a01"
[model.parameters]
m = 1.0
L = 1.0
g = 9.81
[model.body.bob]
kind = "particle"
mass = "m"
[model.joint.rod]
type = "distance"
body2 = "bob"
length = "L"
[model.force.gravity]
type = "gravity"
g = [0, "-g"]
)";
    v.q0 = Eigen::Vector2d(L, 0.0);
    v.k = g / L;
    variants.push_back(v);
  }
  {
    Variant v;  // a uniform bar pinned at its end: J_pivot = m L²/3, k = m g (L/2) / J_pivot
    v.text = R"([model]
name = "a01_bar"
[model.parameters]
m = 1.0
L = 1.0
g = 9.81
[model.body.bar]
mass = "m"
inertia = "m*L^2/12"
markers = { pin = ["-L/2", 0] }
[model.joint.pin]
type = "revolute"
body2 = "bar"
marker2 = "pin"
[model.force.gravity]
type = "gravity"
g = [0, "-g"]
)";
    v.q0 = Eigen::Vector3d(L / 2, 0.0, 0.0);
    v.k = 1.5 * g / L;
    variants.push_back(v);
  }
  for (const Variant& v : variants) {
    const auto desc = load_model_text(v.text, v.text.substr(15, 8));
    const auto model = desc->instantiate({});
    mech::SimulationOptions o;
    o.t_end = t_end;
    o.rtol = 1e-11;
    o.atol = 1e-12;
    o.active_constraints = desc->default_active_constraints();
    const Eigen::VectorXd qd0 = Eigen::VectorXd::Zero(model->n());
    double e_drift = 0.0;
    auto energy = [&](const Eigen::VectorXd& q, const Eigen::VectorXd& qd) {
      Eigen::MatrixXd M(model->n(), model->n());
      Eigen::VectorXd h(model->n());
      model->kinetic_terms(0.0, q, qd, M, h);
      const double yc = model->n() == 2 ? q[1] : q[1];  // the centre of mass height
      return 0.5 * qd.dot(M * qd) + 1.0 * g * yc;
    };
    const double e0 = energy(v.q0, qd0);
    const auto r = mech::simulate(*model, v.q0, qd0, o, [&](const mech::StepView& s) {
      const mech::Sample& x = s.sample(s.t);
      e_drift = std::max(e_drift, std::abs(energy(x.q, x.qd) - e0));
      return true;
    });
    BOOST_REQUIRE(r.status == mech::SimulationStatus::success);
    const double th = pendulum_angle(v.k, 0.0, t_end);
    const double lc = model->n() == 2 ? L : L / 2;  // where q[0], q[1] sit on the pendulum
    BOOST_TEST_MESSAGE(desc->name() << ": x " << r.q_end[0] << " vs " << lc * std::cos(th)
                                    << ", energy drift " << e_drift);
    BOOST_CHECK_SMALL(r.q_end[0] - lc * std::cos(th), 1e-7);
    BOOST_CHECK_SMALL(r.q_end[1] - lc * std::sin(th), 1e-7);
    BOOST_CHECK_LT(e_drift, 1e-7 * g);
  }
}


// ---- generated kinematics (issue 22): angular velocity, angular and marker accelerations ----

namespace {

// A uniform bar (mass m, length L) pinned at one end to ground at (1000, -2000) m (coordinates far
// from the origin), under gravity -g y: placed by a revolute tree joint (one coordinate, phi) or
// as an absolute body (bar_x, bar_y, bar_th) held by a revolute constraint joint.
std::string pinned_bar(bool tree) {
  std::string text = R"([model]
name = "pinned_bar"
[model.parameters]
m = 2.0
L = 0.8
g = 9.81
[model.body.ground]
markers = { pin = [1000, -2000] }
[model.body.bar]
mass = "m"
inertia = "m*L^2/12"
com = ["L/2", 0]
markers = { tip = ["L", 0] }
[model.joint.pin]
type = "revolute"
marker1 = "pin"
body2 = "bar"
)";
  if (tree) text += "coordinates = [\"phi\"]\n";
  text += R"([model.force.gravity]
type = "gravity"
g = [0, "-g"]
[model.outputs]
ax = "bar_tip_ax"
ay = "bar_tip_ay"
w = "bar_w"
alpha = "bar_alpha"
)";
  return text;
}

int column_of(const mech::Model& m, const std::string& name) {
  const auto& names = m.derived_names();
  const auto it = std::find(names.begin(), names.end(), name);
  BOOST_REQUIRE_MESSAGE(it != names.end(), "no output " << name);
  return static_cast<int>(it - names.begin());
}

}  // namespace

// The tip of a pendulum (a bar pinned at one end) accelerates by α L along the tangent and ω² L
// towards the pin, with α = −(3 g / 2 L) cos φ from the equation of motion about the pin
// (J_pin = m L²/3, gravity's moment −m g (L/2) cos φ; φ from the horizontal). At 8 states, for
// the bar on a tree joint and as an absolute body on a constraint joint (its q̈ from the
// engine's solve): bar_tip_ax/_ay, bar_w and bar_alpha equal the closed form to 1e-12 of the
// scale (rounding: the pin sits 1000 and 2000 m from the origin).
BOOST_AUTO_TEST_CASE(pendulum_tip_acceleration_is_centripetal_plus_tangential_from_the_equation_of_motion) {
  const double g = 9.81, L = 0.8;
  for (const bool tree : {true, false}) {
    const auto desc = load_model_text(pinned_bar(tree), tree ? "tree_bar.toml" : "absolute_bar.toml");
    const auto model = desc->instantiate({});
    const int n = model->n();
    BOOST_REQUIRE_EQUAL(n, tree ? 1 : 3);
    std::vector<int> rows;
    for (int i = 0; i < static_cast<int>(model->constraints().size()); ++i) rows.push_back(i);
    mech::Dynamics dyn(*model, Kernel::cpp);
    const auto set = mech::ActiveSet::of(*model, rows);
    const int cax = column_of(*model, "ax"), cay = column_of(*model, "ay"), cw = column_of(*model, "w"),
              ca = column_of(*model, "alpha");
    double worst = 0.0;
    for (const auto& [phi, w] : std::vector<std::pair<double, double>>{
             {0.3, 2.0}, {1.2, -5.0}, {2.5, 7.0}, {-2.0, 0.0}, {-0.7, 3.5}, {3.0, -1.0}, {1.5707963267948966, 4.0}, {0.0, 10.0}}) {
      Eigen::VectorXd q(n), qd(n);
      if (tree) {
        q << phi;
        qd << w;
      } else {
        q << 1000.0, -2000.0, phi;
        qd << 0.0, 0.0, w;
      }
      BOOST_REQUIRE(dyn.evaluate(set, 0.0, q, qd) == mech::ModelIssue::none);
      BOOST_REQUIRE(dyn.solve(mech::ReactionMethod::compatibility) == mech::ModelIssue::none);
      Eigen::VectorXd out(static_cast<Eigen::Index>(model->derived_names().size()));
      model->derived(0.0, q, qd, dyn.qdd, dyn.R, out);
      const double alpha = -1.5 * g * std::cos(phi) / L;
      const double ax = -alpha * L * std::sin(phi) - w * w * L * std::cos(phi);
      const double ay = alpha * L * std::cos(phi) - w * w * L * std::sin(phi);
      const double scale = std::abs(alpha) * L + w * w * L;
      worst = std::max({worst, std::abs(out[cax] - ax) / scale, std::abs(out[cay] - ay) / scale,
                        std::abs(out[ca] - alpha) / scale, std::abs(out[cw] - w) / (1 + std::abs(w))});
    }
    BOOST_TEST_MESSAGE((tree ? "tree joint" : "absolute body") << ": worst relative difference " << worst);
    BOOST_CHECK_LT(worst, 1e-12);
  }
}

namespace {

// Runs `model` and samples the outputs vx, ax on a uniform grid of step h; returns, over the
// interior points, the largest |ax − (vx(t+h) − vx(t−h))/2h| and the largest truncation error
// that the central difference may have there, h²/6 |ä| (ä from the second difference of ax)
// plus the dense output's error over 2h.
struct Difference {
  double worst = 0, allowed = 0, scale = 0;
  int points = 0;
};
Difference central_difference_check(const mech::Model& model, const std::vector<std::string>& active,
                                    const Eigen::VectorXd& q0, const Eigen::VectorXd& qd0, double t_end,
                                    double h, const std::vector<std::pair<std::string, std::string>>& pairs) {
  mech::SimulationOptions o;
  o.t_end = t_end;
  o.rtol = 1e-12;
  o.atol = 1e-12;
  o.active_constraints = active;
  std::vector<int> cv, ca;
  for (const auto& [v, a] : pairs) {
    cv.push_back(column_of(model, v));
    ca.push_back(column_of(model, a));
  }
  std::vector<std::vector<double>> V(pairs.size()), A(pairs.size());
  int next = 0;
  const auto r = mech::simulate(model, q0, qd0, o, [&](const mech::StepView& view) {
    while (next * h <= view.t + 1e-12 && next * h <= t_end) {
      const mech::Sample& s = view.sample(std::min(next * h, view.t));
      for (std::size_t k = 0; k < pairs.size(); ++k) {
        V[k].push_back(s.derived[cv[k]]);
        A[k].push_back(s.derived[ca[k]]);
      }
      ++next;
    }
    return true;
  });
  BOOST_REQUIRE(r.status == mech::SimulationStatus::success);
  Difference d;
  for (std::size_t k = 0; k < pairs.size(); ++k) {
    const std::size_t N = V[k].size();
    std::vector<double> add(N, 0.0);  // |ä| by the second difference of the acceleration column
    for (std::size_t i = 1; i + 1 < N; ++i) add[i] = std::abs(A[k][i + 1] - 2 * A[k][i] + A[k][i - 1]) / (h * h);
    for (std::size_t i = 2; i + 2 < N; ++i) {
      const double cd = (V[k][i + 1] - V[k][i - 1]) / (2 * h);
      const double err = std::abs(A[k][i] - cd);
      // ä's largest value over [t − h, t + h] (the remainder's mean value lies there)
      const double amax = std::max({add[i - 1], add[i], add[i + 1]});
      const double allowed = 1.5 * h * h / 6 * amax + 1e-8 / h + 1e-9 * std::abs(A[k][i]);
      d.worst = std::max(d.worst, err);
      d.allowed = std::max(d.allowed, allowed);
      d.scale = std::max(d.scale, std::abs(A[k][i]));
      if (err > allowed) BOOST_ERROR(pairs[k].second << " at t = " << i * h << ": " << err << " > " << allowed);
      ++d.points;
    }
  }
  return d;
}

}  // namespace

// A double pendulum of two bars, the second placed on the first by a revolute tree joint (its
// tip's velocity and acceleration go through the first body's definitions: the chain rule of
// the derivation), run chaotically for 2 s (rtol 1e-12): at every point of a 1 ms grid the
// output tip acceleration equals the central difference of the tip velocity column to the
// difference's truncation error h²/6 |ä| (h = 1 ms; ä, its largest over [t − h, t + h], from the
// second difference of the acceleration column; 1.5 times that, plus 1e-8/h for Radau's dense
// output between steps, the collocation polynomial, good to ~1e-9 here: the excess over h²/6 |ä|
// grows from 2e-6 to 4e-5 when rtol goes from 1e-12 to 1e-10). The angular velocity and
// acceleration columns of the lower bar likewise. Measured: the worst difference is 0.25 m/s²
// where the bound allows 0.37 (the whip of the lower bar: accelerations up to 251 m/s²).
BOOST_AUTO_TEST_CASE(marker_acceleration_column_is_the_central_difference_of_its_velocity_column) {
  const std::string text = R"([model]
name = "double_bar"
[model.parameters]
m = 1.0
L = 0.5
[model.body.ground]
markers = { pin = [1000, 500] }
[model.body.upper]
mass = "m"
inertia = "m*L^2/12"
com = ["L/2", 0]
markers = { tip = ["L", 0] }
[model.body.lower]
mass = "m"
inertia = "m*L^2/12"
com = ["L/2", 0]
markers = { tip = ["L", 0] }
[model.joint.shoulder]
type = "revolute"
marker1 = "pin"
body2 = "upper"
coordinates = ["a"]
[model.joint.elbow]
type = "revolute"
body1 = "upper"
marker1 = "tip"
body2 = "lower"
coordinates = ["b"]
[model.force.gravity]
type = "gravity"
g = [0, -9.81]
[model.outputs]
vx = "lower_tip_vx"
vy = "lower_tip_vy"
ax = "lower_tip_ax"
ay = "lower_tip_ay"
w = "lower_w"
dw = "lower_alpha"
)";
  const auto desc = load_model_text(text, "double_bar.toml");
  const auto model = desc->instantiate({});
  Eigen::VectorXd q0(2), qd0(2);
  q0 << 0.3, 1.0;
  qd0 << 0.0, 0.0;
  const Difference d = central_difference_check(*model, {}, q0, qd0, 2.0, 1e-3,
                                                {{"vx", "ax"}, {"vy", "ay"}, {"w", "dw"}});
  BOOST_TEST_MESSAGE("worst |a - central difference of v| " << d.worst << " (allowed up to " << d.allowed
                                                            << ") of accelerations up to " << d.scale
                                                            << ", " << d.points << " points");
  BOOST_CHECK_GT(d.points, 5000);
  BOOST_CHECK_GT(d.scale, 10.0);
}

// The accelerations are outputs: a drawing may not use them (the model is refused naming the
// drawing's key), and a definition that uses one may be used only by outputs.
BOOST_AUTO_TEST_CASE(marker_acceleration_in_a_drawing_or_an_equation_is_refused_naming_the_key) {
  std::string text = pinned_bar(true);
  const std::string drawn = text + R"([model.draw]
[[model.draw.point]]
name = "p"
x = "bar_tip_x + 0.1*bar_tip_ax"
y = "bar_tip_y"
[[model.draw.line]]
points = ["p", { x = 0, y = 0 }]
)";
  const std::string e1 = input_error_of([&] { load_model_text(drawn, "drawn.toml"); });
  BOOST_TEST_MESSAGE(e1);
  BOOST_CHECK(contains_all(e1, {"drawn.toml", "model.draw.point[1].x", "bar_tip_ax", "acceleration"}));
  std::string forced = text;
  forced.replace(forced.find("[model.outputs]"), 0, "[model.forces]\nphi = \"-0.1*bar_tip_ax\"\n");
  const std::string e2 = input_error_of([&] { load_model_text(forced, "forced.toml"); });
  BOOST_TEST_MESSAGE(e2);
  BOOST_CHECK(contains_all(e2, {"forced.toml", "model.forces.phi", "bar_tip_ax", "outputs"}));
}
