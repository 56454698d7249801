// ogf-paper2d end to end: the table is printed and the paper's claims hold (d < 0.04, OGF accuracy within
// 1 % of EP's); --samples is applied in file order (the means it writes equal an independent dense OGF);
// --truth reads a PGM; --png draws the figures; bad input is refused with the line named.
#include <gtest/gtest.h>

#include <Eigen/Core>
#include <unistd.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "ogf/filter/dense_ogf.hpp"
#include "ogf/filter/expectation_propagation.hpp"

namespace {

namespace fs = std::filesystem;

struct Output {
  int status = -1;
  std::string text;
};

Output run(const std::string& args) {
  Output out;
  const std::string cmd = std::string(OGF_PAPER2D_BIN) + " " + args + " 2>&1";
  std::FILE* p = ::popen(cmd.c_str(), "r");
  if (p == nullptr) {
    return out;
  }
  char buf[4096];
  std::size_t n = 0;
  while ((n = std::fread(buf, 1, sizeof buf, p)) > 0) {
    out.text.append(buf, n);
  }
  const int rc = ::pclose(p);
  out.status = WIFEXITED(rc) ? WEXITSTATUS(rc) : -1;
  return out;
}

fs::path tempDir() {
  const fs::path d = fs::temp_directory_path() / ("ogf-paper2d-" + std::to_string(::getpid()));
  fs::create_directories(d);
  return d;
}

std::vector<std::vector<double>> tableRows(const std::string& text) {
  std::vector<std::vector<double>> rows;
  std::istringstream in(text);
  std::string line;
  while (std::getline(in, line)) {
    std::istringstream fields(line);
    std::vector<double> values;
    double v = 0.0;
    while (fields >> v) {
      values.push_back(v);
    }
    if (values.size() == 8 && fields.eof()) {
      rows.push_back(values);
    }
  }
  return rows;
}

TEST(Paper2d, TablePrintedAndThePapersClaimsHold) {
  const Output out = run("--strict --counts 30,150,300");
  ASSERT_EQ(out.status, 0) << out.text;
  EXPECT_NE(out.text.find("d(OGF,EP)"), std::string::npos);
  const auto rows = tableRows(out.text);
  ASSERT_EQ(rows.size(), 3U) << out.text;
  for (const auto& r : rows) {
    EXPECT_LT(r[1], 0.04) << "d(OGF, EP) at " << r[0] << " samples";
    EXPECT_LE(std::abs(r[4] - r[3]), 0.01) << "accuracy of OGF vs EP at " << r[0] << " samples";
  }
  // Sec. VI-A: with dense samples EP and the OGF beat occupancy grid mapping (here at 300 of 625).
  EXPECT_GT(rows[2][4], rows[2][2]);
  EXPECT_NE(out.text.find("claim d(OGF,EP) < 0.04 on every row: holds"), std::string::npos);
}

TEST(Paper2d, SamplesFileIsAppliedInFileOrderAndMeansOutMatchesADenseOgf) {
  const fs::path dir = tempDir();
  // Samples on the built-in world's top-left block (rows 3-8, cols 3-10 occupied) and around it.
  const std::vector<std::array<int, 3>> samples = {{4, 4, 1}, {5, 6, 1}, {1, 1, -1}, {12, 12, -1},
                                                   {8, 10, 1}, {4, 4, 1}, {10, 3, -1}, {3, 12, -1}};
  {
    std::ofstream csv(dir / "s.csv");
    csv << "row,col,y\n";
    for (const auto& s : samples) {
      csv << s[0] << "," << s[1] << "," << s[2] << "\n";
    }
  }
  const Output out = run("--samples " + (dir / "s.csv").string() + " --means-out " + (dir / "m.csv").string());
  ASSERT_EQ(out.status, 0) << out.text;

  // Independent computation: the paper's prior on 25 × 25 cells (σ = 1), eq. (5) in file order, and EP.
  Eigen::MatrixXd prior(625, 625);
  for (int a = 0; a < 625; ++a) {
    for (int b = 0; b < 625; ++b) {
      const double dr = a / 25 - b / 25;
      const double dc = a % 25 - b % 25;
      prior(a, b) = std::exp(-(dr * dr + dc * dc) / 2.0) / std::sqrt(2.0 * 3.14159265358979323846);
    }
  }
  ogf::filter::DenseOgf dense(prior);
  std::vector<ogf::filter::EpSite> sites;
  for (const auto& s : samples) {
    dense.update(s[0] * 25 + s[1], s[2]);
    sites.push_back({s[0] * 25 + s[1], s[2]});
  }
  const auto ep = ogf::filter::ExpectationPropagation(prior).run(sites);
  ASSERT_TRUE(ep.ok());

  std::ifstream means(dir / "m.csv");
  std::string line;
  ASSERT_TRUE(std::getline(means, line));
  EXPECT_EQ(line, "row,col,m_ogf,m_ep");
  int count = 0;
  while (std::getline(means, line)) {
    int r = 0;
    int c = 0;
    double mo = 0.0;
    double me = 0.0;
    ASSERT_EQ(std::sscanf(line.c_str(), "%d,%d,%lf,%lf", &r, &c, &mo, &me), 4) << line;
    EXPECT_NEAR(mo, dense.mean()(r * 25 + c), 1e-9);
    EXPECT_NEAR(me, ep->mean(r * 25 + c), 1e-4);
    ++count;
  }
  EXPECT_EQ(count, 625);
  fs::remove_all(dir);
}

TEST(Paper2d, TruthPgmAndPngFiguresAreUsed) {
  const fs::path dir = tempDir();
  {
    std::ofstream pgm(dir / "t.pgm", std::ios::binary);
    pgm << "P5\n# a 12 x 10 world\n12 10\n255\n";
    for (int r = 0; r < 10; ++r) {
      for (int c = 0; c < 12; ++c) {
        pgm.put(static_cast<char>(c < 4 ? 0 : 255));  // left third dark = occupied
      }
    }
  }
  const Output out = run("--truth " + (dir / "t.pgm").string() + " --counts 20,100 --png " + (dir / "fig").string());
  ASSERT_EQ(out.status, 0) << out.text;
  EXPECT_NE(out.text.find("10x12 ground truth"), std::string::npos) << out.text;
  ASSERT_EQ(tableRows(out.text).size(), 2U);
  for (const char* name : {"ground_truth.png", "samples.png", "ep_map.png", "ogf_map.png", "difference.png",
                           "accuracy.png", "difference_vs_samples.png"}) {
    std::ifstream png(dir / "fig" / name, std::ios::binary);
    char sig[8] = {};
    png.read(sig, 8);
    EXPECT_EQ(std::string(sig + 1, 3), "PNG") << name;
  }
  fs::remove_all(dir);
}

TEST(Paper2d, BadSamplesAreRefusedNamingTheLine) {
  const fs::path dir = tempDir();
  {
    std::ofstream csv(dir / "bad.csv");
    csv << "row,col,y\n1,1,1\n2,2,0\n";
  }
  const Output out = run("--samples " + (dir / "bad.csv").string());
  EXPECT_NE(out.status, 0);
  EXPECT_NE(out.text.find("bad.csv:3"), std::string::npos) << out.text;
  fs::remove_all(dir);
}

}  // namespace
