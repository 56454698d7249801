// Inverse Mills ratio: direct ratio where both φ and Φ are normal doubles, a continued fraction in the far
// left tail where Φ(z) underflows.
#include "ogf/filter/inverse_mills.hpp"

#include <cmath>
#include <numbers>

namespace ogf::filter {
namespace {

constexpr double kInvSqrt2Pi = 0.398942280401432677939946059934;  // 1/√(2π)

// Below this z, Φ(z) comes close to the smallest normal double (Φ(-37.5) ≈ 5e-308): use the continued
// fraction of the Mills ratio instead, which converges fast there.
constexpr double kContinuedFractionBelow = -30.0;

// Mills ratio R(t) = Φ(-t)/φ(t) = 1/(t + 1/(t + 2/(t + 3/(t + ...)))) for t > 0 (Laplace's continued
// fraction), evaluated from a fixed depth backwards. For t ≥ 30 forty levels are far below 1e-16.
double millsRatioContinuedFraction(double t) {
  double tail = t;
  for (int k = 40; k >= 1; --k) {
    tail = t + static_cast<double>(k) / tail;
  }
  return 1.0 / tail;
}

}  // namespace

double normalPdf(double z) { return kInvSqrt2Pi * std::exp(-0.5 * z * z); }

double normalCdf(double z) { return 0.5 * std::erfc(-z / std::numbers::sqrt2); }

double inverseMillsRatio(double z) {
  if (z < kContinuedFractionBelow) {
    return 1.0 / millsRatioContinuedFraction(-z);
  }
  // erfc is relatively accurate in its tail, so the ratio of two relatively accurate numbers is too.
  return normalPdf(z) / normalCdf(z);
}

}  // namespace ogf::filter
