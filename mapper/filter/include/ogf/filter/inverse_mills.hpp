// The standard normal pdf, cdf and the inverse Mills ratio λ(z) = φ(z)/Φ(z) that drives the OGF update,
// eq. (5), and the EP moments, eq. (7). λ is computed stably for every z: a map that has seen a cell many
// times pushes z far from 0 in both directions (docs/filter.md §4.1), where φ(z)/Φ(z) by naive division
// breaks down.
#pragma once

namespace ogf::filter {

// φ(z), the standard normal density.
double normalPdf(double z);

// Φ(z), the standard normal cumulative distribution (the probit), relatively accurate in both tails.
double normalCdf(double z);

// λ(z) = φ(z)/Φ(z), relative error below 1e-13 for z in [-40, 40] wherever λ is a normal double
// (for z above about 37.5, λ < 1e-300 and underflows towards 0). Finite for every finite z; for z → -∞,
// λ(z) ≈ -z.
double inverseMillsRatio(double z);

}  // namespace ogf::filter
