// Text on the tools' figures: a 5 × 7 pixel font of printable ASCII (one column of space between glyphs,
// two rows below the baseline for descenders), drawn `size` screen pixels per font pixel. Characters the
// font lacks are drawn as a hollow box, so a missing glyph shows instead of vanishing.
#pragma once

#include <string_view>

#include "ogf/tools/image.hpp"

namespace ogf::tools {

inline constexpr int kGlyphWidth = 5;
inline constexpr int kGlyphHeight = 9;  // 7 rows of ink and 2 of descender
inline constexpr int kGlyphAdvance = 6;

// Width and height in pixels of `text` at `size`.
int textWidth(std::string_view text, int size);
inline int textHeight(int size) { return kGlyphHeight * size; }

// Draws `text` with its top-left corner at (x, y).
void drawText(Image& image, int x, int y, std::string_view text, Rgb colour, int size);

}  // namespace ogf::tools
