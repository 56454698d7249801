// Cell–solid overlap on half-open cells (see cell_overlap.hpp), in units of the grid's cells.
#include "ogf/sim/cell_overlap.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>

#include "units.hpp"

namespace ogf::sim {
namespace {

// The slanted tests' cell: upper faces this far in (in cells), standing for the open upper faces.
constexpr double kOpenFace = 1e-9;

double snapToBoundary(double u) {
  const double n = std::round(u);
  return std::abs(u - n) <= kOnCellBoundary ? n : u;
}

// The closed interval [lo, hi] against the half-open cell interval [k, k + 1).
bool meetsAlong(double lo, double hi, std::int32_t k) { return lo < k + 1.0 && hi >= k; }
// The open interval (lo, hi) holds all of [k, k + 1).
bool holdsAlong(double lo, double hi, std::int32_t k) { return lo < k && hi >= k + 1.0; }

// The cell's footprint with its upper faces moved in: corners (x, y) in cells.
std::array<std::array<double, 2>, 4> footprintCorners(const CellKey& key) {
  const double x0 = key.x;
  const double y0 = key.y;
  const double x1 = key.x + 1.0 - kOpenFace;
  const double y1 = key.y + 1.0 - kOpenFace;
  return {{{x0, y0}, {x1, y0}, {x0, y1}, {x1, y1}}};
}

}  // namespace

CellClassifier::CellClassifier(const Shape& shape, double resolution) {
  const double r = resolution;
  if (const auto* box = std::get_if<Box>(&shape)) {
    const Eigen::Vector3d h = 0.5 * box->size;
    lo_[2] = snapToBoundary((box->centre.z() - h.z()) / r);
    hi_[2] = snapToBoundary((box->centre.z() + h.z()) / r);
    // A yaw that is a whole number of quarter turns leaves the box axis-aligned (odd ones swap its sides).
    const double quarters = box->yaw / (0.5 * std::numbers::pi);
    if (std::abs(quarters - std::round(quarters)) < 1e-12) {
      const bool swapped = static_cast<long long>(std::llround(quarters)) % 2 != 0;
      const double hx = swapped ? h.y() : h.x();
      const double hy = swapped ? h.x() : h.y();
      lo_[0] = snapToBoundary((box->centre.x() - hx) / r);
      hi_[0] = snapToBoundary((box->centre.x() + hx) / r);
      lo_[1] = snapToBoundary((box->centre.y() - hy) / r);
      hi_[1] = snapToBoundary((box->centre.y() + hy) / r);
      kind_ = Kind::AxisBox;
      return;
    }
    kind_ = Kind::YawedBox;
    centre_ = {box->centre.x() / r, box->centre.y() / r};
    half_ = {h.x() / r, h.y() / r};
    yaw_ = box->yaw;
    return;
  }
  if (const auto* cyl = std::get_if<Cylinder>(&shape)) {
    kind_ = Kind::Cylinder;
    lo_[2] = snapToBoundary(cyl->z_min / r);
    hi_[2] = snapToBoundary(cyl->z_max / r);
    centre_ = {cyl->centre.x() / r, cyl->centre.y() / r};
    half_ = {cyl->radius / r, cyl->radius / r};
    return;
  }
  const auto& hs = std::get<HalfSpace>(shape);
  for (int a = 0; a < 3; ++a) {
    if (std::abs(std::abs(hs.normal[a]) - 1.0) < 1e-12) {
      // {±u_a <= offset}: an interval along a, unbounded along the other two axes.
      kind_ = Kind::AxisBox;
      lo_ = {-kInfinity, -kInfinity, -kInfinity};
      hi_ = {kInfinity, kInfinity, kInfinity};
      const double bound = snapToBoundary(hs.offset / r);
      if (hs.normal[a] > 0) {
        hi_[static_cast<std::size_t>(a)] = bound;
      } else {
        lo_[static_cast<std::size_t>(a)] = -bound;
      }
      return;
    }
  }
  kind_ = Kind::TiltedHalfSpace;
  normal_ = {hs.normal.x(), hs.normal.y(), hs.normal.z()};
  offset_ = hs.offset / r;
}

CellOverlap CellClassifier::classify(const CellKey& key) const {
  switch (kind_) {
    case Kind::AxisBox: {
      if (!meetsAlong(lo_[0], hi_[0], key.x) || !meetsAlong(lo_[1], hi_[1], key.y) ||
          !meetsAlong(lo_[2], hi_[2], key.z)) {
        return CellOverlap::None;
      }
      const bool inside = holdsAlong(lo_[0], hi_[0], key.x) && holdsAlong(lo_[1], hi_[1], key.y) &&
                          holdsAlong(lo_[2], hi_[2], key.z);
      return inside ? CellOverlap::Inside : CellOverlap::Surface;
    }
    case Kind::YawedBox: {
      if (!meetsAlong(lo_[2], hi_[2], key.z)) return CellOverlap::None;
      const double c = std::cos(yaw_);
      const double s = std::sin(yaw_);
      const auto corners = footprintCorners(key);
      bool all_inside = holdsAlong(lo_[2], hi_[2], key.z);
      for (const auto& p : corners) {
        const double dx = p[0] - centre_[0];
        const double dy = p[1] - centre_[1];
        const double lx = c * dx + s * dy;
        const double ly = -s * dx + c * dy;
        all_inside = all_inside && std::abs(lx) < half_[0] && std::abs(ly) < half_[1];
      }
      if (all_inside) return CellOverlap::Inside;
      // Separating axes of two rectangles in the plane: the cell's x and y, the box's two yawed axes.
      const std::array<std::array<double, 2>, 4> axes = {{{1, 0}, {0, 1}, {c, s}, {-s, c}}};
      for (const auto& axis : axes) {
        double lo = kInfinity;
        double hi = -kInfinity;
        for (const auto& p : corners) {
          const double d = p[0] * axis[0] + p[1] * axis[1];
          lo = std::min(lo, d);
          hi = std::max(hi, d);
        }
        const double mid = centre_[0] * axis[0] + centre_[1] * axis[1];
        const double reach =
            half_[0] * std::abs(c * axis[0] + s * axis[1]) + half_[1] * std::abs(-s * axis[0] + c * axis[1]);
        if (hi < mid - reach || lo > mid + reach) return CellOverlap::None;
      }
      return CellOverlap::Surface;
    }
    case Kind::Cylinder: {
      if (!meetsAlong(lo_[2], hi_[2], key.z)) return CellOverlap::None;
      const double radius2 = half_[0] * half_[0];
      const double nx = std::clamp(centre_[0], static_cast<double>(key.x), key.x + 1.0 - kOpenFace);
      const double ny = std::clamp(centre_[1], static_cast<double>(key.y), key.y + 1.0 - kOpenFace);
      if ((nx - centre_[0]) * (nx - centre_[0]) + (ny - centre_[1]) * (ny - centre_[1]) > radius2) {
        return CellOverlap::None;
      }
      bool all_inside = holdsAlong(lo_[2], hi_[2], key.z);
      for (const auto& p : footprintCorners(key)) {
        const double dx = p[0] - centre_[0];
        const double dy = p[1] - centre_[1];
        all_inside = all_inside && dx * dx + dy * dy < radius2;
      }
      return all_inside ? CellOverlap::Inside : CellOverlap::Surface;
    }
    case Kind::TiltedHalfSpace: {
      double lo = kInfinity;
      double hi = -kInfinity;
      for (int i = 0; i < 8; ++i) {
        const double x = key.x + ((i & 1) ? 1.0 - kOpenFace : 0.0);
        const double y = key.y + ((i & 2) ? 1.0 - kOpenFace : 0.0);
        const double z = key.z + ((i & 4) ? 1.0 - kOpenFace : 0.0);
        const double d = normal_[0] * x + normal_[1] * y + normal_[2] * z;
        lo = std::min(lo, d);
        hi = std::max(hi, d);
      }
      if (hi < offset_) return CellOverlap::Inside;
      if (lo > offset_) return CellOverlap::None;
      return CellOverlap::Surface;
    }
  }
  return CellOverlap::None;
}

std::optional<std::pair<CellKey, CellKey>> CellClassifier::keyRange() const {
  std::array<double, 3> lo = lo_;
  std::array<double, 3> hi = hi_;
  if (kind_ == Kind::TiltedHalfSpace) return std::nullopt;
  if (kind_ == Kind::YawedBox || kind_ == Kind::Cylinder) {
    const double c = std::abs(std::cos(yaw_));
    const double s = std::abs(std::sin(yaw_));
    const double ex = kind_ == Kind::Cylinder ? half_[0] : half_[0] * c + half_[1] * s;
    const double ey = kind_ == Kind::Cylinder ? half_[0] : half_[0] * s + half_[1] * c;
    lo[0] = centre_[0] - ex;
    hi[0] = centre_[0] + ex;
    lo[1] = centre_[1] - ey;
    hi[1] = centre_[1] + ey;
  }
  for (int a = 0; a < 3; ++a) {
    if (!std::isfinite(lo[static_cast<std::size_t>(a)]) || !std::isfinite(hi[static_cast<std::size_t>(a)])) {
      return std::nullopt;
    }
  }
  // The cell holding each end (a face on a boundary belongs to the cell above it).
  const auto cellOf = [](double v) { return static_cast<std::int32_t>(std::floor(v)); };
  return std::make_pair(CellKey{cellOf(lo[0]), cellOf(lo[1]), cellOf(lo[2])},
                        CellKey{cellOf(hi[0]), cellOf(hi[1]), cellOf(hi[2])});
}

}  // namespace ogf::sim
