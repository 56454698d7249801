// Cell maps drawn 16 pixels per cell; curves drawn on a plain grid (no text: docs/mapping.md names the axes).
#include "ogf/paper2d/figures.hpp"

#include <algorithm>
#include <cmath>
#include <vector>

#include "ogf/filter/occupancy.hpp"
#include "ogf/tools/png_writer.hpp"

namespace ogf::paper2d {
namespace {

constexpr int kCell = 16;
using tools::Image;
using tools::Rgb;

Rgb grey(double darkness) {
  const auto v = static_cast<std::uint8_t>(std::lround(255.0 * (1.0 - std::clamp(darkness, 0.0, 1.0))));
  return {v, v, v};
}

template <class Colour>
Image cellMap(const GroundTruth& truth, Colour colourOf) {
  Image img = Image::rgb(truth.cols * kCell, truth.rows * kCell);
  for (int r = 0; r < truth.rows; ++r) {
    for (int c = 0; c < truth.cols; ++c) {
      img.fillRect(c * kCell, r * kCell, kCell, kCell, colourOf(r, c));
    }
  }
  return img;
}

// A chart of curves y(x): x in [0, xMax], y in [0, yMax], light grid at quarter steps.
struct Chart {
  static constexpr int kWidth = 480;
  static constexpr int kHeight = 320;
  static constexpr int kMargin = 30;
  double xMax;
  double yMax;
  Image img = Image::rgb(kWidth, kHeight);

  int px(double x) const { return kMargin + static_cast<int>(std::lround(x / xMax * (kWidth - 2 * kMargin))); }
  int py(double y) const {
    return kHeight - kMargin - static_cast<int>(std::lround(y / yMax * (kHeight - 2 * kMargin)));
  }
  void frame() {
    for (int q = 1; q <= 4; ++q) {
      img.drawLine(px(0), py(yMax * q / 4), px(xMax), py(yMax * q / 4), {220, 220, 220});
      img.drawLine(px(xMax * q / 4), py(0), px(xMax * q / 4), py(yMax), {220, 220, 220});
    }
    img.drawLine(px(0), py(0), px(xMax), py(0), {0, 0, 0}, 2);
    img.drawLine(px(0), py(0), px(0), py(yMax), {0, 0, 0}, 2);
  }
  void curve(const std::vector<double>& xs, const std::vector<double>& ys, Rgb colour) {
    for (std::size_t i = 0; i < xs.size(); ++i) {
      img.fillRect(px(xs[i]) - 3, py(ys[i]) - 3, 7, 7, colour);
      if (i > 0) {
        img.drawLine(px(xs[i - 1]), py(ys[i - 1]), px(xs[i]), py(ys[i]), colour, 2);
      }
    }
  }
};

}  // namespace

bool writeFigures(const std::filesystem::path& dir, const GroundTruth& truth, std::span<const Sample> samples,
                  std::span<const ExperimentRun> runs, const ExperimentRun& last, std::string& error) {
  std::error_code ec;
  std::filesystem::create_directories(dir, ec);
  if (ec) {
    error = dir.string() + ": " + ec.message();
    return false;
  }
  const auto index = [&](int r, int c) { return static_cast<Eigen::Index>(r * truth.cols + c); };

  // Fig. 2a: ground truth, dark = occupied.
  if (!tools::writePng(dir / "ground_truth.png",
                       cellMap(truth, [&](int r, int c) { return grey(truth.at(r, c) > 0 ? 1.0 : 0.0); }), error)) {
    return false;
  }
  // Fig. 2b: samples, occupied dark red, free light blue, unsampled grey.
  std::vector<int> sampled(truth.cells(), 0);
  for (const Sample& s : samples) {
    sampled[static_cast<std::size_t>(index(s.row, s.col))] = s.y;
  }
  const Image samplesImg = cellMap(truth, [&](int r, int c) -> Rgb {
    const int y = sampled[static_cast<std::size_t>(index(r, c))];
    return y > 0 ? Rgb{150, 20, 20} : y < 0 ? Rgb{170, 210, 255} : Rgb{128, 128, 128};
  });
  if (!tools::writePng(dir / "samples.png", samplesImg, error)) {
    return false;
  }
  // Fig. 3b, 3c: Φ(m) of EP and of the OGF, dark = occupied.
  if (!tools::writePng(dir / "ep_map.png", cellMap(truth, [&](int r, int c) {
                         return grey(filter::occupancyProbability(last.meanEp(index(r, c))));
                       }), error) ||
      !tools::writePng(dir / "ogf_map.png", cellMap(truth, [&](int r, int c) {
                         return grey(filter::occupancyProbability(last.meanOgf(index(r, c))));
                       }), error)) {
    return false;
  }
  // Fig. 3d: |m_ogf − m_ep|, white 0 to red at the largest difference.
  const double largest = std::max(1e-12, (last.meanOgf - last.meanEp).cwiseAbs().maxCoeff());
  const Image diff = cellMap(truth, [&](int r, int c) -> Rgb {
    const double t = std::abs(last.meanOgf(index(r, c)) - last.meanEp(index(r, c))) / largest;
    const auto gb = static_cast<std::uint8_t>(std::lround(255.0 * (1.0 - t)));
    return {255, gb, gb};
  });
  if (!tools::writePng(dir / "difference.png", diff, error)) {
    return false;
  }
  // Fig. 3a and 4a: d and accuracy against the number of samples.
  std::vector<double> xs, d, og, ep, ogf;
  for (const ExperimentRun& run : runs) {
    xs.push_back(static_cast<double>(run.samples));
    d.push_back(run.dOgfEp);
    og.push_back(run.accuracyOg);
    ep.push_back(run.accuracyEp);
    ogf.push_back(run.accuracyOgf);
  }
  const double xMax = xs.empty() ? 1.0 : std::max(1.0, *std::max_element(xs.begin(), xs.end()));
  Chart acc{xMax, 1.0};
  acc.frame();
  acc.curve(xs, og, {0, 0, 0});
  acc.curve(xs, ep, {30, 90, 220});
  acc.curve(xs, ogf, {220, 40, 40});
  Chart dChart{xMax, std::max(0.05, d.empty() ? 0.0 : *std::max_element(d.begin(), d.end()) * 1.1)};
  dChart.frame();
  dChart.img.drawLine(dChart.px(0), dChart.py(0.04), dChart.px(xMax), dChart.py(0.04), {120, 120, 120});
  dChart.curve(xs, d, {220, 40, 40});
  return tools::writePng(dir / "accuracy.png", acc.img, error) &&
         tools::writePng(dir / "difference_vs_samples.png", dChart.img, error);
}

}  // namespace ogf::paper2d
