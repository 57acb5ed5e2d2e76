// Copyright (c) 2026, the activecal authors.
// SPDX-License-Identifier: BSD-3-Clause

#include "activecal/core/puma560.h"

#include <cmath>

namespace activecal {
namespace {

constexpr double kPi = M_PI;
constexpr double kDeg = M_PI / 180.0;

struct Row {
  double gamma, alpha, a, d, beta;
};

Eigen::VectorXd Pack(const Row (&rows)[7]) {
  Eigen::VectorXd v = Eigen::VectorXd::Zero(7 * 6 + kMarkerBlockSize);
  for (int b = 0; b < 7; ++b) {
    double* p = v.data() + b * 6;
    p[kGamma] = rows[b].gamma;
    p[kAlpha] = rows[b].alpha;
    p[kA] = rows[b].a;
    p[kD] = rows[b].d;
    p[kBeta] = rows[b].beta;
    p[kGain] = 1.0;
  }
  return v;
}

}  // namespace

RobotModel Puma560PaperModel() {
  RobotModel m;
  m.name = "puma560_sun_hollerbach";
  m.base.name = "B";
  m.base.convention = LinkConvention::kHayati;
  m.base.joint_type = JointType::kFixed;
  m.base.free = {true, true, true, false, true, false};

  const double lo[6] = {-250, -110, -133, -100, -142, -176};
  const double hi[6] = {70, 170, 133, 100, 142, 356};
  for (int i = 0; i < 6; ++i) {
    Link l;
    l.name = "L" + std::to_string(i + 1);
    l.convention =
        i == 1 ? LinkConvention::kHayati : LinkConvention::kStandardDH;
    l.joint_type = JointType::kRevolute;
    l.joint_min = lo[i] * kDeg;
    l.joint_max = hi[i] * kDeg;
    if (i == 1) {
      l.free = {true, true, true, false, true, false};
    } else if (i == 5) {
      l.free = {true, false, true, true, false, false};
    } else {
      l.free = {true, true, true, true, false, false};
    }
    m.links.push_back(l);
  }
  m.markers[0].free = {false, false, false};
  // Table II.
  const Row nominal[7] = {{1.6360, 0.1572, 19.8820, 0.0, -0.0123},
                          {-0.0367, -1.4524, 0.0603, 0.6713, 0.0},
                          {-0.1455, -0.2622, 0.3411, 0.0, -0.1963},
                          {0.0128, 1.6374, -0.1214, 0.0074, 0.0},
                          {0.0024, -1.3948, -0.1029, 0.3002, 0.0},
                          {0.1207, 1.6151, -0.0468, -0.0747, 0.0},
                          {0.0938, 0.0, 0.1322, 0.3083, 0.0}};
  m.nominal = Pack(nominal);
  return m;
}

Eigen::VectorXd Puma560TrueParameters() {
  // Table I.
  const Row truth[7] = {{kPi / 2, kPi / 100, 20.0, 0.0, kPi / 100},
                        {0.0, -kPi / 2, 0.0, 0.6858, 0.0},
                        {0.0, kPi / 100, 0.4318, 0.0, kPi / 100},
                        {0.0, kPi / 2, -0.0203, 0.1491, 0.0},
                        {0.0, -kPi / 2, 0.0, 0.4331, 0.0},
                        {0.0, kPi / 2, 0.0, 0.0, 0.0},
                        {0.0, 0.0, 0.2, 0.1655, 0.0}};
  return Pack(truth);
}

}  // namespace activecal
