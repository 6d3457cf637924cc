// Not a test of its own: the program the tests of scratch_dir_test.cpp run to watch tests/scratch_dir.h from the
// outside (its folder is removed or kept when the program exits). It writes a file into its
// scratch folder, prints the folder's path, and fails when PROBE_FAIL is set.
#include <gtest/gtest.h>

#include <cstdlib>
#include <fstream>
#include <iostream>

#include "../scratch_dir.h"

TEST(scratch_dir_probe, writes_a_file_and_fails_if_asked) {
  std::ofstream(scratch_dir() / "probe.txt") << "written by the probe\n";
  std::cout << "scratch " << scratch_dir().string() << std::endl;
  if (std::getenv("PROBE_FAIL") != nullptr) ADD_FAILURE() << "PROBE_FAIL is set";
}
