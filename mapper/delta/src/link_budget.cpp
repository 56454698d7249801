#include "ogf/delta/link_budget.hpp"

#include <algorithm>
#include <cmath>

namespace ogf::delta {

LinkBudget::LinkBudget(double bytes_per_s, double burst_s, std::int64_t now_us)
    : rate_(bytes_per_s > 0 ? bytes_per_s : 0.0),
      capacity_(rate_ * std::max(burst_s, 0.0)),
      tokens_(capacity_),
      last_us_(now_us) {}

void LinkBudget::refill(std::int64_t now_us) {
  if (now_us > last_us_) tokens_ = std::min(capacity_, tokens_ + rate_ * static_cast<double>(now_us - last_us_) * 1e-6);
  last_us_ = std::max(last_us_, now_us);
}

std::int64_t LinkBudget::allowance() const {
  if (!bounded()) return kUnbounded;
  return tokens_ > 0 ? static_cast<std::int64_t>(tokens_) : 0;
}

void LinkBudget::spend(std::int64_t bytes) {
  spent_ += bytes;
  if (bounded()) tokens_ -= static_cast<double>(bytes);
}

std::int64_t LinkBudget::debtUs() const {
  if (!bounded() || tokens_ >= 0) return 0;
  return static_cast<std::int64_t>(std::ceil(-tokens_ / rate_ * 1e6));
}

}  // namespace ogf::delta
