// rfm_offline command line and YAML parameters through the option table.

#include "reflectance_field_map/offline/arguments.h"
#include "reflectance_field_map/offline/params.h"

#include <gtest/gtest.h>

#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <fstream>

namespace rfm {
namespace offline {
namespace {

std::string errorOf(const std::vector<std::string>& args) {
  try {
    parseArguments(args);
  } catch (const ArgumentError& e) {
    return e.what();
  }
  return "";
}

TEST(Arguments, Defaults) {
  const OfflineArguments args = parseArguments({"--bag", "in.bag", "--out", "dir"});
  EXPECT_EQ(args.bag, "in.bag");
  EXPECT_EQ(args.out, "dir");
  EXPECT_TRUE(args.params.empty());
  EXPECT_EQ(args.scan_topics, (std::vector<std::string>{"/scan_front", "/scan_rear"}));
  EXPECT_FALSE(args.scan_topics_given);
  EXPECT_EQ(args.fixed_frame, "odom");
  EXPECT_EQ(args.base_frame, "base_link");
  EXPECT_FALSE(args.no_motion_removal);
  EXPECT_FALSE(args.no_reflection_removal);
  EXPECT_FALSE(args.baseline);
  EXPECT_FALSE(args.theta_view.has_value());
}

TEST(Arguments, EveryFlag) {
  const OfflineArguments args = parseArguments(
      {"--bag", "a.bag", "--out", "o", "--params", "p.yaml", "--scan-topics", "/a,/b,/c",
       "--fixed-frame", "map", "--base-frame", "base_footprint", "--no-motion-removal",
       "--no-reflection-removal", "--baseline", "--theta-view", "-1.5,2,3,4.25"});
  EXPECT_EQ(args.params, "p.yaml");
  EXPECT_EQ(args.scan_topics, (std::vector<std::string>{"/a", "/b", "/c"}));
  EXPECT_TRUE(args.scan_topics_given);
  EXPECT_EQ(args.fixed_frame, "map");
  EXPECT_EQ(args.base_frame, "base_footprint");
  EXPECT_TRUE(args.no_motion_removal);
  EXPECT_TRUE(args.no_reflection_removal);
  EXPECT_TRUE(args.baseline);
  ASSERT_TRUE(args.theta_view.has_value());
  EXPECT_EQ(*args.theta_view, (std::array<double, 4>{-1.5, 2.0, 3.0, 4.25}));
}

TEST(Arguments, EqualsForm) {
  const OfflineArguments args =
      parseArguments({"--bag=x.bag", "--out=d", "--scan-topics=/scan", "--fixed-frame=laser"});
  EXPECT_EQ(args.bag, "x.bag");
  EXPECT_EQ(args.scan_topics, (std::vector<std::string>{"/scan"}));
  EXPECT_EQ(args.fixed_frame, "laser");
}

TEST(Arguments, HelpNeedsNothingElse) {
  EXPECT_TRUE(parseArguments({"--help"}).help);
  EXPECT_TRUE(parseArguments({"-h"}).help);
  EXPECT_NE(usage().find("--theta-view"), std::string::npos);
  EXPECT_NE(usage().find("--no-reflection-removal"), std::string::npos);
}

TEST(Arguments, ClearErrors) {
  EXPECT_NE(errorOf({"--out", "d"}).find("--bag"), std::string::npos);
  EXPECT_NE(errorOf({"--bag", "b"}).find("--out"), std::string::npos);
  EXPECT_NE(errorOf({}).find("required"), std::string::npos);
  EXPECT_NE(errorOf({"--bag", "b", "--out", "d", "--frobnicate"}).find("--frobnicate"),
            std::string::npos);
  EXPECT_NE(errorOf({"--bag", "b", "--out", "d", "extra"}).find("extra"), std::string::npos);
  EXPECT_NE(errorOf({"--bag"}).find("--bag needs a value"), std::string::npos);
  EXPECT_NE(errorOf({"--bag", "--out", "d"}).find("--bag needs a value"), std::string::npos);
  EXPECT_NE(errorOf({"--bag=", "--out", "d"}).find("--bag needs a value"), std::string::npos);
  EXPECT_NE(errorOf({"--bag", "b", "--out", "d", "--baseline=1"}).find("takes no value"),
            std::string::npos);
  EXPECT_NE(errorOf({"--bag", "b", "--out", "d", "--scan-topics", "/a,,/b"}).find("empty topic"),
            std::string::npos);
  EXPECT_NE(errorOf({"--bag", "b", "--out", "d", "--theta-view", "1,2,3"}).find("four"),
            std::string::npos);
  EXPECT_NE(errorOf({"--bag", "b", "--out", "d", "--theta-view", "1,2,x,4"}).find("'x'"),
            std::string::npos);
  EXPECT_NE(errorOf({"--bag", "b", "--out", "d", "--theta-view", "1,2,1,2"}).find("same"),
            std::string::npos);
  EXPECT_NE(errorOf({"--bag", "b", "--out", "d", "--fixed-frame="}).find("--fixed-frame"),
            std::string::npos);
}

struct ModeCase {
  std::vector<std::string> flags;
  BatchMode mode;
  bool motion_enabled;
  bool reflection_enabled;
  std::string name;
};

TEST(Arguments, ModeFromFlags) {
  const std::vector<ModeCase> cases = {
      {{}, BatchMode::kFull, true, true, "full"},
      {{"--baseline"}, BatchMode::kPlainGrid, true, true, "plain_grid"},
      {{"--baseline", "--no-motion-removal"}, BatchMode::kPlainGrid, true, true, "plain_grid"},
      {{"--no-motion-removal", "--no-reflection-removal"},
       BatchMode::kBasicRfm,
       false,
       false,
       "basic_rfm"},
      {{"--no-reflection-removal"}, BatchMode::kMotionRemoval, true, false, "motion_removal"},
      {{"--no-motion-removal"}, BatchMode::kFull, false, true, "reflection_removal"},
  };
  for (const ModeCase& c : cases) {
    std::vector<std::string> argv = {"--bag", "b", "--out", "d"};
    argv.insert(argv.end(), c.flags.begin(), c.flags.end());
    MapperOptions options;
    const ModeSelection selection = selectMode(parseArguments(argv), options);
    EXPECT_EQ(selection.mode, c.mode) << c.name;
    EXPECT_EQ(selection.name, c.name);
    EXPECT_EQ(options.motion_removal.motion_removal_enabled, c.motion_enabled) << c.name;
    EXPECT_EQ(options.reflection_removal.reflection_removal_enabled, c.reflection_enabled)
        << c.name;
  }
}

TEST(Arguments, ParamsSwitchCountsLikeTheFlag) {
  MapperOptions options;
  options.reflection_removal.reflection_removal_enabled = false;
  EXPECT_EQ(selectMode(parseArguments({"--bag", "b", "--out", "d"}), options).mode,
            BatchMode::kMotionRemoval);
}

// --- YAML parameters -------------------------------------------------------------------------

std::string invalidOptionField(const std::string& yaml) {
  MapperOptions options;
  try {
    loadParamsText(yaml, options);
    options.validate();
  } catch (const InvalidOption& e) {
    EXPECT_NE(std::string(e.what()).find(e.field()), std::string::npos);
    return e.field();
  }
  return "";
}

TEST(Params, SetsOptionsByName) {
  MapperOptions options;
  const ParamsReport report = loadParamsText(
      "resolution: 0.1\ntheta_bins: 90\nmotion_removal_enabled: false\n"
      "reflection_removal_enabled: 1\nbeta: 20\nscan_topics: [/a, /b]\nfixed_frame: map\n",
      options);
  EXPECT_DOUBLE_EQ(options.grid.resolution, 0.1);
  EXPECT_EQ(options.grid.theta_bins, 90);
  EXPECT_FALSE(options.motion_removal.motion_removal_enabled);
  EXPECT_TRUE(options.reflection_removal.reflection_removal_enabled);
  EXPECT_DOUBLE_EQ(options.occupancy.beta, 20.0);
  EXPECT_EQ(report.applied.size(), 5u);
  EXPECT_EQ(report.ignored, (std::vector<std::string>{"scan_topics", "fixed_frame"}));
  EXPECT_NO_THROW(options.validate());
}

TEST(Params, NestedNamespacesLoad) {
  MapperOptions options;
  const ParamsReport report =
      loadParamsText("rfm_node:\n  grid:\n    resolution: 0.02\n  alpha: 0.05\n", options);
  EXPECT_DOUBLE_EQ(options.grid.resolution, 0.02);
  EXPECT_DOUBLE_EQ(options.occupancy.alpha, 0.05);
  EXPECT_EQ(report.applied.size(), 2u);
}

TEST(Params, EveryOptionRoundTrips) {
  // Writing every option of a default MapperOptions and loading it gives the same options.
  MapperOptions defaults;
  std::string yaml;
  for (const OptionField& field : optionFields()) {
    char line[128];
    std::snprintf(line, sizeof(line), "%s: %.17g\n", field.name.c_str(),
                  getOption(defaults, field.name));
    yaml += line;
  }
  const BatchOptions batch_defaults;
  for (const OptionField& field : batchOptionFields()) {
    char line[128];
    std::snprintf(line, sizeof(line), "%s: %.17g\n", field.name.c_str(),
                  getOption(batch_defaults, field.name));
    yaml += line;
  }
  MapperOptions loaded;
  loaded.grid.resolution = 0.3;  // changed, must come back
  BatchOptions loaded_batch;
  loaded_batch.batch_beta = 99.0;
  const ParamsReport report = loadParamsText(yaml, loaded, loaded_batch);
  EXPECT_EQ(report.applied.size(), optionFields().size() + batchOptionFields().size());
  for (const OptionField& field : optionFields()) {
    EXPECT_DOUBLE_EQ(getOption(loaded, field.name), getOption(defaults, field.name)) << field.name;
  }
  for (const OptionField& field : batchOptionFields()) {
    EXPECT_DOUBLE_EQ(getOption(loaded_batch, field.name), getOption(batch_defaults, field.name))
        << field.name;
  }
  // A live mapper's load leaves the batch's keys aside.
  MapperOptions live;
  const ParamsReport live_report = loadParamsText(yaml, live);
  EXPECT_EQ(live_report.applied.size(), optionFields().size());
  EXPECT_EQ(live_report.ignored.size(), batchOptionFields().size());
}

TEST(Params, BadValuesNameTheParameter) {
  EXPECT_EQ(invalidOptionField("theta_bins: lots\n"), "theta_bins");
  EXPECT_EQ(invalidOptionField("resolution: [1, 2]\n"), "resolution");
  EXPECT_EQ(invalidOptionField("beta:\n"), "beta");
  EXPECT_EQ(invalidOptionField("resolution: -0.05\n"), "resolution");
  EXPECT_EQ(invalidOptionField("group:\n  log_odds_hit: 0\n"), "log_odds_hit");
  EXPECT_EQ(invalidOptionField("resolution: 0.05\n"), "");
}

TEST(Params, UnreadableFiles) {
  MapperOptions options;
  try {
    loadParamsFile("/nonexistent/params.yaml", options);
    FAIL() << "no error";
  } catch (const ParamsError& e) {
    EXPECT_NE(std::string(e.what()).find("/nonexistent/params.yaml"), std::string::npos);
  }
  EXPECT_THROW(loadParamsText("resolution: [0.1\n", options), ParamsError);
  EXPECT_THROW(loadParamsText("- a\n- b\n", options), ParamsError);
  EXPECT_NO_THROW(loadParamsText("", options));
}

TEST(Params, LoadsFromAFile) {
  const std::string path = (std::filesystem::temp_directory_path() /
                            ("rfm_params_test_" + std::to_string(::getpid()) + ".yaml"))
                               .string();
  {
    std::ofstream out(path);
    out << "# comment\nclearing_distance: 2.5\n";
  }
  MapperOptions options;
  loadParamsFile(path, options);
  EXPECT_DOUBLE_EQ(options.insertion.clearing_distance, 2.5);
  std::filesystem::remove(path);
}

TEST(Params, ShippedConfigFilesLoad) {
  const std::filesystem::path config = std::filesystem::path(RFM_SOURCE_DIR) / "config";
  if (!std::filesystem::is_directory(config)) GTEST_SKIP() << "no config/ directory";
  int files = 0;
  for (const auto& entry : std::filesystem::directory_iterator(config)) {
    if (entry.path().extension() != ".yaml") continue;
    MapperOptions options;
    EXPECT_NO_THROW({
      loadParamsFile(entry.path().string(), options);
      options.validate();
    }) << entry.path();
    ++files;
  }
  if (files == 0) GTEST_SKIP() << "no config/*.yaml yet";
}

// config/default.yaml documents the defaults: every core option it lists must equal the code's
// default, and it must list them all.
TEST(Params, DefaultYamlMatchesTheCoreDefaults) {
  const std::filesystem::path path = std::filesystem::path(RFM_SOURCE_DIR) / "config/default.yaml";
  MapperOptions from_yaml;
  BatchOptions batch_from_yaml;
  loadParamsFile(path.string(), from_yaml, batch_from_yaml);
  const MapperOptions defaults;
  for (const OptionField& field : optionFields()) {
    EXPECT_NEAR(getOption(from_yaml, field.name), getOption(defaults, field.name),
                1e-9 * std::max(1.0, std::abs(getOption(defaults, field.name))))
        << field.name << " in config/default.yaml differs from the core default";
  }
  const BatchOptions batch_defaults;
  for (const OptionField& field : batchOptionFields()) {
    EXPECT_NEAR(getOption(batch_from_yaml, field.name), getOption(batch_defaults, field.name),
                1e-9 * std::max(1.0, std::abs(getOption(batch_defaults, field.name))))
        << field.name << " in config/default.yaml differs from the batch default";
  }
  std::ifstream text(path);
  const std::string yaml((std::istreambuf_iterator<char>(text)), std::istreambuf_iterator<char>());
  for (const auto* table : {&optionFields(), &batchOptionFields()}) {
    for (const OptionField& field : *table) {
      EXPECT_NE(yaml.find("\n" + field.name + ":"), std::string::npos)
          << field.name << " is missing from config/default.yaml";
    }
  }
}

}  // namespace
}  // namespace offline
}  // namespace rfm
