// Whitespace-separated fields of one text line and strict number parsing (std::from_chars: the whole
// field must be a finite number), shared by the CARMEN log and relations readers.
#pragma once

#include <cstddef>
#include <optional>
#include <string_view>
#include <vector>

namespace ogf::slam_io::detail {

// The fields of `line` split on spaces and tabs (a trailing '\r' counts as whitespace).
std::vector<std::string_view> splitFields(std::string_view line);

// The field as a finite double, or nullopt when it is not entirely one.
std::optional<double> parseDouble(std::string_view field);

// The field as a non-negative count, or nullopt.
std::optional<std::size_t> parseCount(std::string_view field);

}  // namespace ogf::slam_io::detail
