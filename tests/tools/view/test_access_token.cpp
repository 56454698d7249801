// Who may use ogf-view (tools/lib/view/include/ogf/view/access_token.hpp): which --bind addresses are
// loopback, the constant-time comparison's answers, and where a request carries its token.
#include <gtest/gtest.h>

#include "ogf/view/access_token.hpp"

namespace {

using namespace ogf::view;

TEST(AccessToken, OnlyLoopbackAddressesAreLoopback) {
  for (const char* a : {"127.0.0.1", "127.0.0.2", "127.255.255.254", "::1", "::ffff:127.0.0.1"})
    EXPECT_TRUE(isLoopbackAddress(a)) << a;
  for (const char* a : {"0.0.0.0", "::", "192.168.1.10", "10.0.0.1", "128.0.0.1", "::ffff:10.0.0.1", "fe80::1",
                        "localhost", "", "127.0.0.1 "})
    EXPECT_FALSE(isLoopbackAddress(a)) << a;
}

TEST(AccessToken, TokensAreEqualOnlyWhenEveryByteAndTheLengthAgree) {
  EXPECT_TRUE(tokensEqual("0123456789abcdef", "0123456789abcdef"));
  EXPECT_FALSE(tokensEqual("0123456789abcdef", "0123456789abcdee"));
  EXPECT_FALSE(tokensEqual("1123456789abcdef", "0123456789abcdef"));
  EXPECT_FALSE(tokensEqual("0123456789abcdef", "0123456789abcdef0"));
  EXPECT_FALSE(tokensEqual("0123456789abcdef", ""));
  EXPECT_FALSE(tokensEqual(std::string_view("ab\0", 3), "ab"));
}

TEST(AccessToken, TheTokenIsFoundInTheQueryOrTheCookieOnly) {
  EXPECT_EQ(tokenInTarget("/ws?token=abc"), "abc");
  EXPECT_EQ(tokenInTarget("/?x=1&token=abc&y=2"), "abc");
  EXPECT_EQ(tokenInTarget("/?token=abc#frag"), "abc");
  EXPECT_EQ(tokenInTarget("/?token="), "");
  EXPECT_FALSE(tokenInTarget("/ws"));
  EXPECT_FALSE(tokenInTarget("/?mytoken=abc"));
  EXPECT_FALSE(tokenInTarget("/token=abc"));
  EXPECT_EQ(tokenInCookie("ogf_view_token=abc"), "abc");
  EXPECT_EQ(tokenInCookie("a=1; ogf_view_token=abc; b=2"), "abc");
  EXPECT_FALSE(tokenInCookie("xogf_view_token=abc"));
  EXPECT_FALSE(tokenInCookie(""));
}

TEST(AccessToken, TokensThatAreShortOrNeedEscapingAreRefused) {
  EXPECT_FALSE(tokenProblem("0123456789abcdef"));
  EXPECT_FALSE(tokenProblem("A-b.c_d~0123456789"));
  EXPECT_TRUE(tokenProblem("0123456789abcde"));
  EXPECT_TRUE(tokenProblem(""));
  EXPECT_TRUE(tokenProblem("0123456789abcdef&x=1"));
  EXPECT_TRUE(tokenProblem("0123456789abcdef 0"));
}

}  // namespace
