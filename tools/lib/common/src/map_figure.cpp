// Layout of a readable top-down map: see map_figure.hpp.
#include "ogf/tools/map_figure.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <cmath>

#include "ogf/tools/bitmap_font.hpp"

namespace ogf::tools {
namespace {

constexpr Rgb kInk{20, 20, 20};
constexpr Rgb kFrame{90, 90, 90};
constexpr int kText = 2;        // font pixel size of labels
constexpr int kTitleText = 3;   // ... of the title
constexpr int kMaxMapSide = 2400;
constexpr int kLeft = 90, kTop = 80, kRightPanel = 260, kBottom = 80, kGap = 16;

// The number of decimals that prints every multiple of `step` exactly enough.
int decimalsFor(double step) { return step >= 1.0 ? 0 : static_cast<int>(std::ceil(-std::log10(step) - 1e-9)); }

std::string metres(double v, int decimals) { return fmt::format("{:.{}f}", std::abs(v) < 1e-9 ? 0.0 : v, decimals); }

void drawFrame(Image& img, int x, int y, int w, int h, Rgb c) {
  img.fillRect(x - 1, y - 1, w + 2, 1, c);
  img.fillRect(x - 1, y + h, w + 2, 1, c);
  img.fillRect(x - 1, y - 1, 1, h + 2, c);
  img.fillRect(x + w, y - 1, 1, h + 2, c);
}

// Ticks along both axes at multiples of a nice step, labelled in metres.
void drawAxes(Image& img, const MapRaster& r, int scale, int mapX, int mapY, int mapW, int mapH) {
  const double widthM = r.width * r.resolution, heightM = r.height * r.resolution;
  const double step = niceStep(std::max(widthM, heightM) / 8.0);
  const int dec = decimalsFor(step);
  const double pxPerM = scale / r.resolution;
  for (double v = std::ceil(r.x0 / step - 1e-9) * step; v <= r.x0 + widthM + 1e-9; v += step) {
    const int px = mapX + static_cast<int>(std::lround((v - r.x0) * pxPerM));
    img.fillRect(px, mapY + mapH, 1, 8, kFrame);
    const std::string label = metres(v, dec);
    drawText(img, px - textWidth(label, kText) / 2, mapY + mapH + 12, label, kInk, kText);
  }
  for (double v = std::ceil(r.y0 / step - 1e-9) * step; v <= r.y0 + heightM + 1e-9; v += step) {
    const int py = mapY + mapH - static_cast<int>(std::lround((v - r.y0) * pxPerM));
    img.fillRect(mapX - 8, py, 8, 1, kFrame);
    const std::string label = metres(v, dec);
    drawText(img, mapX - 12 - textWidth(label, kText), py - textHeight(kText) / 3, label, kInk, kText);
  }
  const std::string xName = "x (m)";
  drawText(img, mapX + mapW / 2 - textWidth(xName, kText) / 2, mapY + mapH + 12 + textHeight(kText) + 8, xName, kInk,
           kText);
  drawText(img, mapX - 12 - textWidth("y (m)", kText), mapY - textHeight(kText) - 10, "y (m)", kInk, kText);
}

// A bar of a nice length in metres, with its length written under it; returns the height used.
int drawScaleBar(Image& img, const MapRaster& r, int scale, int x, int y, int maxWidth) {
  const double pxPerM = scale / r.resolution;
  double length = niceStep(maxWidth * 0.6 / pxPerM);
  while (length * pxPerM > maxWidth && length > 1e-6) length = niceStep(length / 2.5);
  const int px = std::max(1, static_cast<int>(std::lround(length * pxPerM)));
  drawText(img, x, y, "scale", kInk, kText);
  const int barY = y + textHeight(kText) + 6;
  img.fillRect(x, barY, px, 6, kInk);
  img.fillRect(x, barY - 4, 2, 14, kInk);
  img.fillRect(x + px - 2, barY - 4, 2, 14, kInk);
  const std::string label = metres(length, decimalsFor(length)) + " m";
  drawText(img, x, barY + 16, label, kInk, kText);
  return barY + 16 + textHeight(kText) - y;
}

int drawLegend(Image& img, const std::vector<LegendEntry>& legend, int x, int y) {
  int yy = y;
  for (const LegendEntry& e : legend) {
    img.fillRect(x, yy, 22, 22, e.colour);
    drawFrame(img, x, yy, 22, 22, kFrame);
    drawText(img, x + 32, yy + 4, e.label, kInk, kText);
    yy += 34;
  }
  return yy - y;
}

int drawColourBar(Image& img, const ColourBar& bar, int x, int y) {
  constexpr int kBarH = 220, kBarW = 26;
  drawText(img, x, y, bar.label, kInk, kText);
  const int top = y + textHeight(kText) + 8;
  for (int i = 0; i < kBarH; ++i) {
    const double t = 1.0 - static_cast<double>(i) / (kBarH - 1);
    img.fillRect(x, top + i, kBarW, 1, bar.colour(t));
  }
  drawFrame(img, x, top, kBarW, kBarH, kFrame);
  drawText(img, x + kBarW + 10, top, bar.hi, kInk, kText);
  drawText(img, x + kBarW + 10, top + kBarH - textHeight(kText) + 4, bar.lo, kInk, kText);
  return top + kBarH - y;
}

}  // namespace

double niceStep(double rough) {
  if (!(rough > 0.0) || !std::isfinite(rough)) return 1.0;
  const double decade = std::pow(10.0, std::floor(std::log10(rough)));
  for (const double m : {1.0, 2.0, 5.0, 10.0}) {
    if (m * decade >= rough * (1.0 - 1e-9)) return m * decade;
  }
  return 10.0 * decade;
}

Rgb sequentialColour(double t) {
  // Anchors chosen to rise steadily in lightness: dark blue, blue, teal, green, yellow.
  static constexpr std::array<std::array<double, 3>, 5> kAnchors{{
      {{30, 20, 90}}, {{40, 90, 170}}, {{30, 150, 150}}, {{90, 195, 80}}, {{245, 230, 40}}}};
  t = std::clamp(std::isfinite(t) ? t : 0.0, 0.0, 1.0) * (kAnchors.size() - 1);
  const auto i = std::min(static_cast<std::size_t>(t), kAnchors.size() - 2);
  const double f = t - static_cast<double>(i);
  Rgb c{};
  for (std::size_t k = 0; k < 3; ++k) {
    c[k] = static_cast<std::uint8_t>(std::lround(kAnchors[i][k] + f * (kAnchors[i + 1][k] - kAnchors[i][k])));
  }
  return c;
}

Image composeMapFigure(const MapRaster& r, const std::string& title, const std::string& note, const FigureKey& key,
                       int min_scale) {
  const int longSide = std::max({r.width, r.height, 1});
  int scale = std::max({1, min_scale, (kFigureMinLongSide + longSide - 1) / longSide});
  scale = std::max(1, std::min(scale, kMaxMapSide / longSide));
  const int mapW = r.width * scale, mapH = r.height * scale;
  const int panelH = 520;
  const int width = kLeft + mapW + kGap + kRightPanel;
  const int height = kTop + std::max(mapH, panelH) + kBottom;
  Image img = Image::rgb(width, height);
  drawText(img, kLeft, 14, title, kInk, kTitleText);
  drawText(img, kLeft, 14 + textHeight(kTitleText) + 4, note, {90, 90, 90}, kText);
  const int mapX = kLeft, mapY = kTop;
  for (int row = 0; row < r.height; ++row) {
    for (int col = 0; col < r.width; ++col) {
      img.fillRect(mapX + col * scale, mapY + row * scale, scale, scale,
                   r.cells[static_cast<std::size_t>(row) * static_cast<std::size_t>(r.width) + static_cast<std::size_t>(col)]);
    }
  }
  drawFrame(img, mapX, mapY, mapW, mapH, kFrame);
  drawAxes(img, r, scale, mapX, mapY, mapW, mapH);
  const int panelX = mapX + mapW + kGap + 20;
  int y = mapY;
  if (!key.legend.empty()) y += drawLegend(img, key.legend, panelX, y) + 14;
  if (key.colour_bar) y += drawColourBar(img, *key.colour_bar, panelX, y) + 24;
  drawScaleBar(img, r, scale, panelX, y, kRightPanel - 40);
  return img;
}

}  // namespace ogf::tools
