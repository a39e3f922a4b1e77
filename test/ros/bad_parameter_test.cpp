// rfm_node must refuse to start on a bad parameter: non-zero exit status and the parameter's
// name in its error output. Runs the node binary against the master rostest started.
#include <gtest/gtest.h>

#include <sys/wait.h>
#include <array>
#include <cstdio>
#include <string>

namespace {

struct Result {
  int status = -1;
  std::string output;
};

// Runs rfm_node with `args` (stderr merged into stdout); the node name is unique per call so
// the private parameters of one case do not leak into the next.
Result runNode(const std::string& name, const std::string& args) {
  const std::string command =
      std::string("timeout 60 ") + RFM_NODE_BINARY + " __name:=" + name + " " + args + " 2>&1";
  Result result;
  FILE* pipe = popen(command.c_str(), "r");
  if (pipe == nullptr) return result;
  std::array<char, 512> buffer;
  while (fgets(buffer.data(), buffer.size(), pipe) != nullptr)
    result.output += buffer.data();
  const int status = pclose(pipe);
  result.status = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  return result;
}

void expectRejected(const std::string& name, const std::string& args,
                    const std::string& parameter) {
  const Result result = runNode(name, args);
  EXPECT_NE(result.status, 0) << args << " was accepted:\n" << result.output;
  EXPECT_NE(result.status, 124) << args << ": the node did not exit (timeout)";
  EXPECT_NE(result.output.find(parameter), std::string::npos)
      << "the error for " << args << " does not name " << parameter << ":\n"
      << result.output;
  EXPECT_NE(result.output.find("FATAL"), std::string::npos) << result.output;
}

TEST(BadParameter, NegativeResolution) {
  expectRejected("rfm_bad_resolution", "_resolution:=-1", "resolution");
}

TEST(BadParameter, ResolutionNamesItsAllowedRange) {
  const Result result = runNode("rfm_bad_resolution_range", "_resolution:=-1");
  EXPECT_NE(result.output.find("[0.005, 1]"), std::string::npos) << result.output;
}

TEST(BadParameter, NonIntegerThetaBins) {
  expectRejected("rfm_bad_theta_bins", "_theta_bins:=2.5", "theta_bins");
}

TEST(BadParameter, BetaBelowTwoPi) {
  expectRejected("rfm_bad_beta", "_beta:=1.0", "beta");
}

TEST(BadParameter, WrongTypeOfRate) {
  expectRejected("rfm_bad_rate", "_map_publish_rate:=fast", "map_publish_rate");
}

TEST(BadParameter, ZeroMotionRemovalRate) {
  expectRejected("rfm_bad_motion_rate", "_motion_removal_rate:=0", "motion_removal_rate");
}

TEST(BadParameter, EmptyScanTopics) {
  expectRejected("rfm_bad_topics", "_scan_topics:=[]", "scan_topics");
}

TEST(BadParameter, ScanTopicsWithTheSameLastComponent) {
  expectRejected("rfm_bad_topics_leaf", "\"_scan_topics:=[/a/scan, /b/scan]\"", "scan_topics");
}

TEST(BadParameter, ZeroRobotSpeedNamesItsRange) {
  expectRejected("rfm_bad_speed", "_max_robot_speed:=0", "max_robot_speed");
  const Result result = runNode("rfm_bad_speed_range", "_max_robot_speed:=-3");
  EXPECT_NE(result.output.find("(0, 1000]"), std::string::npos) << result.output;
}

// The map must hold at least the active region around the robot (10 m radius: 21 m across).
TEST(BadParameter, MapExtentSmallerThanTheActiveRegion) {
  expectRejected("rfm_bad_extent", "_max_map_extent:=15", "max_map_extent");
}

TEST(BadParameter, EmptyMapDirectory) {
  expectRejected("rfm_bad_map_directory", "_map_directory:=''", "map_directory");
}

}  // namespace

int main(int argc, char** argv) {
  testing::InitGoogleTest(&argc, argv);
  return RUN_ALL_TESTS();
}
