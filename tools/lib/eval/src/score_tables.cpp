// The tables ogf-eval prints: see score_tables.hpp.
#include "ogf/eval/score_tables.hpp"

#include <fmt/format.h>

#include <cstdarg>
#include <cstdio>

namespace ogf::eval {
namespace {

// printf-style formatting appended to `out`: the tables' widths are printf's.
void appendf(std::string& out, const char* format, ...) __attribute__((format(printf, 2, 3)));
void appendf(std::string& out, const char* format, ...) {
  va_list args;
  va_start(args, format);
  va_list again;
  va_copy(again, args);
  const int n = std::vsnprintf(nullptr, 0, format, args);
  va_end(args);
  if (n > 0) {
    const std::size_t at = out.size();
    out.resize(at + static_cast<std::size_t>(n) + 1);
    std::vsnprintf(out.data() + at, static_cast<std::size_t>(n) + 1, format, again);
    out.resize(at + static_cast<std::size_t>(n));
  }
  va_end(again);
}

}  // namespace

MapColumn makeColumn(std::string name, const sim::GroundTruth& truth, const std::vector<CellEstimate>& estimates,
                     const std::vector<std::uint8_t>& ray_end, std::string map_cells) {
  MapColumn c{std::move(name), scoreMap(truth.cells, estimates, ray_end), 0, 0, std::move(map_cells), std::nullopt};
  for (const auto& e : estimates) {
    c.occupied_cells += e.cell_class > 0 ? 1 : 0;
    c.free_cells += e.cell_class < 0 ? 1 : 0;
  }
  return c;
}

std::string scoreTable(const std::vector<MapColumn>& cols, bool gaps) {
  std::string out;
  appendf(out, "%-34s", "metric");
  for (const auto& c : cols) appendf(out, " %12s", c.name.c_str());
  appendf(out, "\n");
  const auto row = [&](const char* label, auto get) {
    appendf(out, "%-34s", label);
    for (const auto& c : cols) appendf(out, " %12s", get(c).c_str());
    appendf(out, "\n");
  };
  const auto f4 = [](double v) { return fmt::format("{:.4f}", v); };
  const auto i64 = [](std::int64_t v) { return fmt::format("{}", v); };
  row("known truth cells (free+occupied)", [&](const MapColumn& c) { return i64(c.scores.known); });
  row("accuracy (eq. 13, unknown = wrong)", [&](const MapColumn& c) { return f4(c.scores.accuracy); });
  row("precision (occupied)", [&](const MapColumn& c) { return f4(c.scores.precision); });
  row("recall (occupied)", [&](const MapColumn& c) { return f4(c.scores.recall); });
  row("ROC AUC (probability)", [&](const MapColumn& c) { return f4(c.scores.auc); });
  row("coverage (known cells classified)", [&](const MapColumn& c) { return f4(c.scores.coverage); });
  if (gaps) {
    row("gap cells (truth occ., no ray end)", [&](const MapColumn& c) { return i64(c.scores.gap_cells); });
    row("gap cells classified occupied", [&](const MapColumn& c) { return i64(c.scores.gap_filled); });
    row("gap filling (share)", [&](const MapColumn& c) { return f4(c.scores.gap_fill); });
    row("filled wrongly (truth free)", [&](const MapColumn& c) { return i64(c.scores.false_filled); });
  }
  if (!cols.empty() && cols.front().swept) {
    row("moving solid: swept free cells", [&](const MapColumn& c) { return i64(c.swept->cells); });
    row("... left occupied", [&](const MapColumn& c) { return i64(c.swept->left_occupied); });
  }
  row("occupied cells (in truth grid)", [&](const MapColumn& c) { return i64(c.occupied_cells); });
  row("free cells (in truth grid)", [&](const MapColumn& c) { return i64(c.free_cells); });
  row("correct cells", [&](const MapColumn& c) { return i64(c.scores.correct); });
  row("cells held by the map", [&](const MapColumn& c) { return c.map_cells; });
  return out;
}

std::string pairTable(const std::string& title, const std::vector<std::string>& names, const TableRows& rows) {
  std::string out;
  appendf(out, "\n%s\n%-34s", title.c_str(), "metric");
  for (const auto& n : names) appendf(out, " %12s", n.c_str());
  appendf(out, "\n");
  for (const auto& [label, values] : rows) {
    appendf(out, "%-34s", label.c_str());
    for (const auto& v : values) appendf(out, " %12s", v.c_str());
    appendf(out, "\n");
  }
  return out;
}

std::string heldOutTable(const HeldOutSplit& split, std::uint64_t seed, const std::vector<std::string>& names,
                         const std::vector<HeldOutScores>& scores) {
  const auto col = [&](auto get) {
    std::vector<std::string> v;
    for (const auto& s : scores) v.push_back(get(s));
    return v;
  };
  return pairTable(
      fmt::format("held-out rays: maps built from the other rays ({:.0f} % held out of every scan, seed {})",
                  100.0 * split.share(), seed),
      names,
      {{"held-out rays", col([](const HeldOutScores& s) { return fmt::format("{}", s.rays); })},
       {"end cells / crossed cells",
        col([](const HeldOutScores& s) { return fmt::format("{}/{}", s.positives, s.negatives); })},
       {"held-out ROC AUC", col([](const HeldOutScores& s) { return fmt::format("{:.4f}", s.auc); })},
       {"end cells classed occupied",
        col([](const HeldOutScores& s) { return fmt::format("{:.4f}", s.positives_occupied); })},
       {"crossed cells classed free",
        col([](const HeldOutScores& s) { return fmt::format("{:.4f}", s.negatives_free); })},
       {"unseen cells: end / crossed",
        col([](const HeldOutScores& s) { return fmt::format("{}/{}", s.unseen.positives, s.unseen.negatives); })},
       {"unseen cells: ROC AUC", col([](const HeldOutScores& s) { return fmt::format("{:.4f}", s.unseen.auc); })}});
}

std::string returnsTable(double from_m, double to_m, const std::vector<ReturnScores>& scores,
                         const std::vector<std::string>& map_cells) {
  const auto col = [&](auto get) {
    std::vector<std::string> v;
    for (const auto& x : scores) v.push_back(fmt::format("{:.4f}", get(x)));
    return v;
  };
  std::vector<std::string> returns;
  for (const auto& x : scores) returns.push_back(fmt::format("{}", x.returns));
  return pairTable(fmt::format("the capture's own returns ({:.1f}-{:.1f} m), both maps built from every return; "
                               "OctoMap through insertPointCloud",
                               from_m, to_m),
                   {"OGF", "OctoMap"},
                   {{"returns", returns},
                    {"return cells classed occupied", col([](const ReturnScores& x) { return x.occupied; })},
                    {"return cells classed free", col([](const ReturnScores& x) { return x.free; })},
                    {"return cells unknown", col([](const ReturnScores& x) { return x.unknown; })},
                    {"half-way points classed free", col([](const ReturnScores& x) { return x.halfway_free; })},
                    {"cells held by the map", map_cells}});
}

}  // namespace ogf::eval
