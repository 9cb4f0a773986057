// The test suite's scratch files go to this build directory's tests/tmp/, not to /tmp: two checkouts
// testing at once on one machine (two engineers, or CI beside a developer) wrote the same /tmp/debris_*
// files and failed each other's tests. ::testing::TempDir() reads TEST_TMPDIR at each call, so setting it
// before main() moves every test's files; a TEST_TMPDIR the user set wins.
#include <gtest/gtest.h>

#include <cstdlib>
#include <string>

namespace {

const bool kUserChoseTheDirectory = std::getenv("TEST_TMPDIR") != nullptr;
const bool kScratchDirectorySet = setenv("TEST_TMPDIR", DEBRIS_TEST_TMPDIR, 0) == 0;

TEST(ScratchDirectory, TestsWriteUnderTheirBuildDirectory) {
  ASSERT_TRUE(kScratchDirectorySet);
  if (kUserChoseTheDirectory) GTEST_SKIP() << "TEST_TMPDIR was set by the user: " << std::getenv("TEST_TMPDIR");
  EXPECT_EQ(::testing::TempDir(), std::string(DEBRIS_TEST_TMPDIR));
  EXPECT_NE(::testing::TempDir(), "/tmp/");
}

}  // namespace
