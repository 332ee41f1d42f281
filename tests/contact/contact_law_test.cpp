// The contact law: values against the paper's formulas, partials against finite differences,
// and the extremes of the parameter space.

#include <cmath>

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "idto/contact/contact_law.hpp"
#include "idto/core/errors.hpp"
#include "support/eigen_matchers.hpp"
#include "support/random.hpp"

namespace idto {
namespace {

ContactParameters Params(double k, double sigma, double vs, double mu = 0.7, double vd = 0.1) {
  ContactParameters p;
  p.stiffness = k;
  p.smoothing = sigma;
  p.stiction_velocity = vs;
  p.friction_coefficient = mu;
  p.dissipation_velocity = vd;
  return p;
}

TEST(ContactLaw, MatchesThePapersFormulasInTheRegularRange) {
  const ContactParameters p = Params(2000.0, 0.01, 0.05, 0.5, 0.1);
  const Eigen::Vector3d n(0, 0, 1);
  for (double phi : {-0.02, -0.001, 0.0, 0.004, 0.03}) {
    for (double vn : {-0.3, -0.05, 0.0, 0.05, 0.15, 0.25}) {
      const Eigen::Vector3d vt(0.03, -0.02, 0.0);
      const ContactForce f = CalcContactForce(p, phi, vn, vt, n);
      const double c = p.smoothing * p.stiffness * std::log(1.0 + std::exp(-phi / p.smoothing));
      const double x = vn / p.dissipation_velocity;
      const double d = x < 0 ? 1 - x : (x < 2 ? (x - 2) * (x - 2) / 4 : 0.0);
      EXPECT_NEAR(f.compliance, c, 1e-12 * c);
      EXPECT_NEAR(f.dissipation, d, 1e-15);
      EXPECT_NEAR(f.fn, c * d, 1e-12 * std::max(1.0, c * d));
      const Eigen::Vector3d ft =
          -p.friction_coefficient * vt /
          std::sqrt(p.stiction_velocity * p.stiction_velocity + vt.squaredNorm()) * c * d;
      EXPECT_EIGEN_NEAR(f.ft, ft, 1e-12 * std::max(1.0, c * d));
      EXPECT_EIGEN_NEAR(f.f, Eigen::Vector3d(c * d * n + ft), 1e-12 * std::max(1.0, c * d));
      // Coulomb cone and maximum dissipation.
      EXPECT_LE(f.ft.norm(), p.friction_coefficient * f.fn + 1e-15);
      EXPECT_LE(f.ft.dot(vt), 0.0);
    }
  }
}

TEST(ContactLaw, PartialsMatchFiniteDifferences) {
  test::Random rng(3);
  const Eigen::Vector3d n = Eigen::Vector3d(0.3, -0.2, 0.9).normalized();
  for (int trial = 0; trial < 200; ++trial) {
    const ContactParameters p =
        Params(rng.Uniform(10, 1e4), rng.Uniform(1e-3, 2e-2), rng.Uniform(0.01, 0.2));
    const double phi = rng.Uniform(-0.03, 0.03);
    double vn = rng.Uniform(-0.4, 0.4);
    // Stay away from the kinks of the dissipation's second derivative (x = 0 and 2 are C1).
    Eigen::Vector3d vt = rng.Vector(3, -0.2, 0.2);
    vt -= vt.dot(n) * n;
    const ContactForce f = CalcContactForce(p, phi, vn, vt, n);
    const double h = 1e-7;
    const ContactForce fp = CalcContactForce(p, phi + h, vn, vt, n);
    const ContactForce fm = CalcContactForce(p, phi - h, vn, vt, n);
    const double scale = std::max(1.0, std::abs(f.dfn_dphi));
    EXPECT_NEAR(f.dfn_dphi, (fp.fn - fm.fn) / (2 * h), 1e-6 * scale);
    EXPECT_EIGEN_NEAR(f.dft_dphi, Eigen::Vector3d((fp.ft - fm.ft) / (2 * h)), 1e-6 * scale);
    const ContactForce gp = CalcContactForce(p, phi, vn + h, vt, n);
    const ContactForce gm = CalcContactForce(p, phi, vn - h, vt, n);
    const double scale_v = std::max(1.0, std::abs(f.dfn_dvn));
    EXPECT_NEAR(f.dfn_dvn, (gp.fn - gm.fn) / (2 * h), 1e-5 * scale_v);
    EXPECT_EIGEN_NEAR(f.dft_dvn, Eigen::Vector3d((gp.ft - gm.ft) / (2 * h)), 1e-5 * scale_v);
    for (int i = 0; i < 3; ++i) {
      Eigen::Vector3d dv = Eigen::Vector3d::Zero();
      dv(i) = h;
      const Eigen::Vector3d col = (CalcContactForce(p, phi, vn, vt + dv, n).ft -
                                   CalcContactForce(p, phi, vn, vt - dv, n).ft) /
                                  (2 * h);
      EXPECT_EIGEN_NEAR(Eigen::Vector3d(f.dft_dvt.col(i)), col,
                        1e-5 * std::max(1.0, f.dft_dvt.norm()));
    }
  }
}

TEST(ContactLaw, FrictionIsZeroAtZeroSlipWithAFiniteDerivative) {
  const ContactParameters p = Params(1000.0, 0.005, 0.05, 0.2);
  const ContactForce f =
      CalcContactForce(p, -0.001, 0.0, Eigen::Vector3d::Zero(), Eigen::Vector3d::UnitZ());
  EXPECT_GT(f.fn, 0.0);
  EXPECT_EQ(f.ft.norm(), 0.0);
  EXPECT_TRUE(f.dft_dvt.allFinite());
  // d ft / d vt at vt = 0 is -mu fn / vs times the identity.
  EXPECT_EIGEN_NEAR(f.dft_dvt,
                    Eigen::Matrix3d(-p.friction_coefficient * f.fn / p.stiction_velocity *
                                    Eigen::Matrix3d::Identity()),
                    1e-12 * f.fn / p.stiction_velocity);
}

TEST(ContactLaw, DissipationIsContinuouslyDifferentiableAtItsBreakpoints) {
  const ContactParameters p = Params(1.0, 1.0, 1.0, 0.0, 0.1);
  for (double vn : {0.0, 0.2}) {
    double dl, dr, gl, gr;
    DissipationAndDerivative(p, vn - 1e-12, &dl, &gl);
    DissipationAndDerivative(p, vn + 1e-12, &dr, &gr);
    EXPECT_NEAR(dl, dr, 1e-10);
    EXPECT_NEAR(gl, gr, 1e-9);
  }
}

TEST(ContactLaw, FiniteAtTheExtremesOfTheParameterSpace) {
  const Eigen::Vector3d n = Eigen::Vector3d::UnitZ();
  for (double k : {1.0, 2e2, 2e4, 2e6, 2e8}) {
    for (double sigma : {1e-5, 1e-3, 1e-2}) {
      for (double vs : {1e-4, 1e-3, 5e-2}) {
        const ContactParameters p = Params(k, sigma, vs);
        for (double ratio : {-1e6, -1e3, -1.0, 0.0, 1.0, 1e3, 1e6}) {
          const double phi = ratio * sigma;
          for (double vt_mag : {0.0, 1e-9, 1e-3, 10.0}) {
            const ContactForce f = CalcContactForce(p, phi, -0.5, Eigen::Vector3d(vt_mag, 0, 0), n);
            SCOPED_TRACE(::testing::Message() << "k=" << k << " sigma=" << sigma << " vs=" << vs
                                              << " phi/sigma=" << ratio);
            EXPECT_TRUE(std::isfinite(f.fn));
            EXPECT_GE(f.fn, 0.0);
            EXPECT_TRUE(f.f.allFinite());
            EXPECT_TRUE(std::isfinite(f.dfn_dphi));
            EXPECT_TRUE(std::isfinite(f.dfn_dvn));
            EXPECT_TRUE(f.dft_dvt.allFinite());
            EXPECT_TRUE(f.dft_dphi.allFinite());
            // Deep penetration: the linear spring k |phi| (times d = 1 + 5 at v_n = -0.5).
            if (ratio == -1e6) {
              EXPECT_NEAR(f.fn, k * (-phi) * 6.0, 1e-9 * f.fn);
            }
            // Far away: exactly zero force is fine, negative or NaN is not.
            if (ratio == 1e6) {
              EXPECT_LT(f.fn, 1e-300);
            }
          }
        }
      }
    }
  }
}

TEST(ContactLaw, CutoffDistanceBoundsTheForce) {
  for (double tol : {1e-9, 1e-6, 1e-3, 1.0, 1e3}) {
    const ContactParameters p = Params(2000.0, 0.01, 0.1);
    const double phi_cut = ContactCutoffDistance(p, tol);
    double c, dc;
    ComplianceAndDerivative(p, phi_cut, &c, &dc);
    EXPECT_NEAR(c, tol, 1e-9 * tol) << tol;
    ComplianceAndDerivative(p, phi_cut + 1e-6, &c, &dc);
    EXPECT_LT(c, tol);
  }
  // sigma log(sigma k / tol) asymptotics: 0.01 * log(20 / 1e-6) = 0.168 m.
  EXPECT_NEAR(ContactCutoffDistance(Params(2000.0, 0.01, 0.1), 1e-6), 0.01 * std::log(2e7), 1e-8);
  // A huge tolerance gives a finite (negative) cut-off.
  EXPECT_TRUE(std::isfinite(ContactCutoffDistance(Params(1.0, 1e-5, 0.1), 1e9)));
}

TEST(ContactLaw, InvalidParametersNameTheField) {
  using ::testing::HasSubstr;
  ContactParameters p;
  p.stiffness = -1.0;
  EXPECT_THAT([&] { p.Validate("scene.yaml: contact"); },
              ::testing::ThrowsMessage<InvalidArgument>(
                  AllOf(HasSubstr("scene.yaml: contact"), HasSubstr("contact stiffness is -1"))));
  p = ContactParameters{};
  p.stiction_velocity = 0.0;
  EXPECT_THAT([&] { p.Validate("x"); },
              ::testing::ThrowsMessage<InvalidArgument>(HasSubstr("stiction_velocity is 0")));
  p = ContactParameters{};
  p.smoothing = std::nan("");
  EXPECT_THAT([&] { p.Validate("x"); },
              ::testing::ThrowsMessage<InvalidArgument>(HasSubstr("smoothing is nan")));
  EXPECT_THAT([&] { ContactCutoffDistance(ContactParameters{}, 0.0); },
              ::testing::ThrowsMessage<InvalidArgument>(HasSubstr("force_tolerance is 0")));
}

}  // namespace
}  // namespace idto
