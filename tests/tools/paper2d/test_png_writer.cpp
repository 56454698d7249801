// The PNG writer's checksums are the standard ones, and a real inflater (python3's zlib) reads its files
// back to the same pixels with valid chunk CRCs.
#include <gtest/gtest.h>

#include <unistd.h>

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <string>

#include "ogf/tools/png_writer.hpp"
#include "ogf/tools/zlib_stream.hpp"

namespace ogf::tools {
namespace {

std::span<const std::uint8_t> bytesOf(const char* s) {
  return {reinterpret_cast<const std::uint8_t*>(s), std::char_traits<char>::length(s)};
}

TEST(PngWriter, Adler32MatchesItsCheckValue) {
  EXPECT_EQ(adler32(bytesOf("Wikipedia")), 0x11E60398U);
}

TEST(PngWriter, PythonZlibReadsTheFileBackToTheSamePixels) {
  if (std::system("python3 -c 'import zlib' >/dev/null 2>&1") != 0) {
    GTEST_SKIP() << "python3 with zlib not available";
  }
  // 300 × 120 RGB of varied pixels.
  Image img = Image::rgb(300, 120);
  for (int y = 0; y < img.height; ++y) {
    for (int x = 0; x < img.width; ++x) {
      img.set(x, y, {static_cast<std::uint8_t>(x), static_cast<std::uint8_t>(y), static_cast<std::uint8_t>(x ^ y)});
    }
  }
  const auto dir = std::filesystem::temp_directory_path() / ("ogf-png-" + std::to_string(::getpid()));
  std::filesystem::create_directories(dir);
  std::string error;
  ASSERT_TRUE(writePng(dir / "t.png", img, error)) << error;
  const std::string script =
      "import zlib,struct,sys\n"
      "d=open(sys.argv[1],'rb').read()\n"
      "assert d[:8]==b'\\x89PNG\\r\\n\\x1a\\n'\n"
      "p=8;idat=b'';w=h=0\n"
      "while p<len(d):\n"
      "  n,=struct.unpack('>I',d[p:p+4]);t=d[p+4:p+8];c=d[p+8:p+8+n]\n"
      "  crc,=struct.unpack('>I',d[p+8+n:p+12+n]);assert crc==zlib.crc32(t+c),t\n"
      "  if t==b'IHDR': w,h=struct.unpack('>II',c[:8]);assert c[8:10]==b'\\x08\\x02'\n"
      "  if t==b'IDAT': idat+=c\n"
      "  p+=12+n\n"
      "raw=zlib.decompress(idat);row=1+3*w;assert len(raw)==row*h\n"
      "for y in range(h):\n"
      "  assert raw[y*row]==0\n"
      "  for x in range(w):\n"
      "    assert raw[y*row+1+3*x:y*row+4+3*x]==bytes([x&255,y&255,(x^y)&255]),(x,y)\n"
      "print('ok',w,h)\n";
  const auto scriptPath = dir / "check.py";
  std::FILE* f = std::fopen(scriptPath.c_str(), "w");
  ASSERT_NE(f, nullptr);
  std::fputs(script.c_str(), f);
  std::fclose(f);
  const std::string cmd = "python3 " + scriptPath.string() + " " + (dir / "t.png").string();
  EXPECT_EQ(std::system(cmd.c_str()), 0);
  std::filesystem::remove_all(dir);
}

TEST(PngWriter, UnwritablePathIsAnErrorNamingIt) {
  std::string error;
  EXPECT_FALSE(writePng("/nonexistent/dir/x.png", Image::rgb(2, 2), error));
  EXPECT_NE(error.find("/nonexistent/dir/x.png"), std::string::npos);
}

}  // namespace
}  // namespace ogf::tools
