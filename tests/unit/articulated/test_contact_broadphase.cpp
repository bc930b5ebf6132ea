// Sweep and prune (contact_broadphase.cpp): the same body-body contacts, in the same
// order, as the full scan of every pair, while testing far fewer pairs.
#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <sstream>

#include "pliant/articulated/io.h"
#include "pliant/articulated/sim.h"

namespace pliant::articulated {
namespace {

void expect_same_contacts(const Model& m, const VecX& q, size_t* found, size_t* candidates) {
  Kinematics k;
  kinematics(m, q, &k);
  const std::vector<GeomPair> pairs = contact_geom_pairs(m);
  PairBroadphase bp = pair_broadphase(m, pairs);
  std::vector<PairContact> full, pruned;
  find_pair_contacts(m, k, pairs, &full, true);
  find_pair_contacts(m, k, pairs, &pruned, true, &bp);
  ASSERT_EQ(full.size(), pruned.size());
  for (size_t i = 0; i < full.size(); ++i) {
    EXPECT_EQ(full[i].body_a, pruned[i].body_a) << i;
    EXPECT_EQ(full[i].body_b, pruned[i].body_b) << i;
    EXPECT_EQ(full[i].depth, pruned[i].depth) << i;
    EXPECT_EQ(full[i].point, pruned[i].point) << i;
    EXPECT_EQ(full[i].normal, pruned[i].normal) << i;
  }
  *found = full.size();
  *candidates = bp.candidates.size();
  // Without self-collision only the explicit pairs and capsule sides count, both ways.
  find_pair_contacts(m, k, pairs, &full, false);
  find_pair_contacts(m, k, pairs, &pruned, false, &bp);
  ASSERT_EQ(full.size(), pruned.size());
  for (size_t i = 0; i < full.size(); ++i) EXPECT_EQ(full[i].depth, pruned[i].depth) << i;
}

// 80 free spheres, capsules and boxes (margins on some) tossed into a box `spread`
// m long and 0.6 m wide and high, an explicit pair, capsules against a static box.
Model random_pile(double spread) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(0, 1);
  std::ostringstream x;
  x << "<mujoco><worldbody><geom type=\"box\" size=\"0.2 0.2 0.05\" pos=\"0.3 0.3 0\"/>";
  for (int b = 0; b < 80; ++b) {
    x << "<body name=\"b" << b << "\" pos=\"" << spread * u(rng) << " " << 0.6 * u(rng) << " " << 0.6 * u(rng)
      << "\" euler=\"" << 360 * u(rng) << " " << 360 * u(rng) << " " << 360 * u(rng) << "\"><freejoint/>";
    const double r = 0.02 + 0.04 * u(rng);
    const char* margin = b % 7 == 0 ? " margin=\"0.01\"" : "";
    if (b % 3 == 0) x << "<geom name=\"g" << b << "\" type=\"sphere\" size=\"" << r << "\"" << margin << "/>";
    if (b % 3 == 1) x << "<geom name=\"g" << b << "\" type=\"capsule\" size=\"" << r << " " << 2 * r << "\"" << margin << "/>";
    if (b % 3 == 2) x << "<geom name=\"g" << b << "\" type=\"box\" size=\"" << r << " " << 0.7 * r << " " << 1.3 * r << "\"" << margin << "/>";
    x << "</body>";
  }
  x << "</worldbody><contact><pair geom1=\"g1\" geom2=\"g2\"/></contact></mujoco>";
  return model_from_mjcf(x.str(), "pile.xml");
}

// Packed into a 0.6 m cube: many overlaps of every shape pair, and the sweep along
// any axis keeps about half the pairs. Spread along 6 m it keeps a small share.
TEST(ContactBroadphase, RandomPileFindsTheFullScansContactsInItsOrder) {
  const Model packed = random_pile(0.6);
  size_t found = 0, candidates = 0;
  expect_same_contacts(packed, state_init(packed).qpos, &found, &candidates);
  EXPECT_GT(found, 40u);
  const size_t filtered = pair_broadphase(packed, contact_geom_pairs(packed)).filtered;
  EXPECT_EQ(filtered, 80u * 79u / 2 - 1);  // all but the explicit pair
  const Model spread = random_pile(6);
  expect_same_contacts(spread, state_init(spread).qpos, &found, &candidates);
  EXPECT_GT(found, 0u);
  EXPECT_LT(candidates, filtered / 8) << "the sweep should test a small share of the pairs";
}

// MuJoCo's 22 humanoids (libmujoco-samples), folded at random configurations, all
// torsos moved within 1 m of each other so that limbs of different humanoids touch.
TEST(ContactBroadphase, TwentyTwoHumanoidsFindTheFullScansContacts) {
  MjcfOptions options;
  options.ignore_solver_params = true;
  const Model m = model_load_file(std::string(PLIANT_MUJOCO_MODEL_DIR) + "/humanoid/22_humanoids.xml",
                                  "22_humanoids.xml", options);
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(-1, 1);
  for (int trial = 0; trial < 3; ++trial) {
    VecX q = state_init(m).qpos;
    for (const Joint& j : m.joints) {
      if (j.type == JointType::Free) {
        q.segment<3>(j.qadr) = Vec3(0.5 * u(rng), 0.5 * u(rng), 0.5 + 0.5 * u(rng));
        q.segment<4>(j.qadr + 3) = Eigen::Vector4d(u(rng), u(rng), u(rng), u(rng)).normalized();
      } else if (j.type == JointType::Hinge) {
        q[j.qadr] = u(rng);
      }
    }
    size_t found = 0, candidates = 0;
    expect_same_contacts(m, q, &found, &candidates);
    EXPECT_GT(found, 50u) << trial;
  }
  // As the file places them (two rows of 11, 1 m apart), limbs folded: each humanoid's geoms meet
  // their own and a neighbour's in the sweep, a small share of the 86k pairs.
  VecX q = state_init(m).qpos;
  for (const Joint& j : m.joints)
    if (j.type == JointType::Hinge) q[j.qadr] = 0.8 * u(rng);
  size_t found = 0, candidates = 0;
  expect_same_contacts(m, q, &found, &candidates);
  EXPECT_LT(candidates, pair_broadphase(m, contact_geom_pairs(m)).filtered / 10);
}

}  // namespace
}  // namespace pliant::articulated
