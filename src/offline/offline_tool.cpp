#include "reflectance_field_map/offline/offline_tool.h"

#include "reflectance_field_map/core/batch_processor.h"
#include "reflectance_field_map/offline/bag_input.h"
#include "reflectance_field_map/offline/outputs.h"
#include "reflectance_field_map/offline/params.h"
#include "reflectance_field_map/offline/progress.h"
#include "reflectance_field_map/render/map_image.h"
#include "reflectance_field_map/render/png_io.h"
#include "reflectance_field_map/render/theta_view.h"

#include <algorithm>
#include <chrono>
#include <filesystem>
#include <functional>
#include <future>
#include <optional>
#include <ostream>

namespace rfm {
namespace offline {
namespace {

using Clock = std::chrono::steady_clock;

double secondsSince(Clock::time_point start) {
  return std::chrono::duration<double>(Clock::now() - start).count();
}

std::string joinPath(const std::string& dir, const std::string& name) {
  return (std::filesystem::path(dir) / name).string();
}

// Writes the theta-resolved picture of the cells along the --theta-view segment.
void writeThetaView(const std::string& path, const render::ThetaSlice& slice, std::ostream& log) {
  const int column_px = std::clamp(800 / std::max(slice.columns, 1), 1, 8);
  render::writePng(path, render::renderThetaSlice(slice, column_px, 2));
  log << "theta view: " << slice.columns << " cells x " << slice.bins << " bins";
  if (slice.outsideColumns() > 0) {
    log << " (" << slice.outsideColumns()
        << " cells outside the final active region: shown dark grey, their bins are archived)";
  }
  log << "\n";
}

}  // namespace

int runOffline(const OfflineArguments& args, std::ostream& log) {
  const Clock::time_point start = Clock::now();
  RunSummary summary;

  // Options: defaults, then the --params file, then the flags.
  MapperOptions options;
  BatchOptions batch;
  ModeSelection mode;
  try {
    if (!args.params.empty()) {
      const ParamsReport report = loadParamsFile(args.params, options, batch);
      log << "parameters: " << report.applied.size() << " set from " << args.params;
      if (!report.ignored.empty()) {
        log << " (ignored, not mapper options:";
        for (const std::string& key : report.ignored)
          log << ' ' << key;
        log << ")";
      }
      log << "\n";
    }
    mode = selectMode(args, options);
    options.validate();
    batch.validate();
  } catch (const InvalidOption& e) {
    log << "rfm_offline: invalid parameter: " << e.what() << "\n";
    return 2;
  } catch (const ParamsError& e) {
    log << "rfm_offline: " << e.what() << "\n";
    return 2;
  }

  try {
    // Bag -> scans with poses.
    Clock::time_point stage = Clock::now();
    BagInputOptions input_options;
    input_options.bag = args.bag;
    input_options.scan_topics = args.scan_topics;
    input_options.fixed_frame = args.fixed_frame;
    input_options.base_frame = args.base_frame;
    input_options.max_speed = args.max_speed;
    BagScans input;
    {
      ProgressBar bar("reading");
      input = readBagScans(input_options,
                           [&bar](size_t done, size_t total) { bar.update(done, total); });
    }
    summary.stage_seconds["read_bag"] = secondsSince(stage);
    for (const std::string& topic : input.missing_topics) {
      log << "rfm_offline: warning: scan topic " << topic << " is not in the bag, skipped\n";
    }
    for (const std::string& note : input.notes)
      log << "rfm_offline: note: " << note << "\n";
    const char* skip_level = args.strict ? "error" : "warning";
    for (const std::string& line : input.describeSkips())
      log << "rfm_offline: " << skip_level << ": skipped " << line << "\n";
    if (args.strict && input.scansSkipped() > 0) {
      log << "rfm_offline: --strict: " << input.scansSkipped() << " of " << input.scansRead()
          << " scans cannot be mapped; nothing written\n";
      return 1;
    }
    log << "read " << input.scans.size() << " scans to map (" << input.duration << " s) from";
    for (size_t t = 0; t < input.topics.size(); ++t) {
      log << ' ' << input.topics[t] << " (" << input.scans_per_topic[t] << ")";
    }
    log << ", " << input.tf_messages << " TF messages\n";

    makeOutputDirectory(args.out);

    // The whole recording through the mapper.
    stage = Clock::now();
    std::optional<render::ThetaSlice> theta_slice;
    std::function<void(const ReflectanceField&)> inspect;
    if (args.theta_view) {
      const auto& s = *args.theta_view;
      inspect = [&theta_slice, &s](const ReflectanceField& field) {
        theta_slice = render::sampleThetaSlice(
            field, render::segmentColumns(field.geometry(), {s[0], s[1]}, {s[2], s[3]}));
      };
    }
    BatchResult result;
    {
      ProgressBar bar("mapping");
      result = processBatch(
          input.scans, options, batch, mode.mode,
          [&bar](size_t done, size_t total) { bar.update(done, total); }, inspect);
    }
    summary.stage_seconds["process"] = secondsSince(stage);

    // Outputs: the labels bag on a thread of its own while the map files are written (tens of
    // milliseconds each, on one core).
    std::future<double> labels_written = std::async(std::launch::async, [&] {
      const Clock::time_point labels_start = Clock::now();
      writeLabelsBag(joinPath(args.out, "labels.bag"), "/rfm/ray_labels", input, result.labels);
      return secondsSince(labels_start);
    });
    stage = Clock::now();
    writeMapServerFiles(args.out, "map", result.map, options.grid.resolution);
    writeClassesPgm(args.out, result.map);
    summary.files = {"map.yaml", "map.pgm", "classes.pgm"};
    const int scale = render::autoScale(result.map.bounds());
    const render::RgbImage layers = render::renderMap(result.map, scale);
    if (!layers.empty()) {
      render::writePng(joinPath(args.out, "layers.png"), layers);
      summary.files.push_back("layers.png");
    } else {
      log << "rfm_offline: warning: the map is empty, layers.png not written\n";
    }
    summary.stage_seconds["write_map"] = secondsSince(stage);
    summary.stage_seconds["write_labels"] = labels_written.get();
    summary.files.push_back("labels.bag");

    if (args.theta_view) {
      if (!theta_slice) {
        log << "rfm_offline: warning: theta_view.png not written: "
            << (mode.mode == BatchMode::kPlainGrid
                    ? "the plain grid (--baseline) has no reflectance field"
                    : "the batch did not expose its field")
            << "\n";
      } else {
        // Reflective bins take the colour of the cell's final class.
        for (int c = 0; c < theta_slice->columns; ++c) {
          theta_slice->column_class[static_cast<size_t>(c)] =
              result.map.get(theta_slice->column_cell[static_cast<size_t>(c)]);
        }
        writeThetaView(joinPath(args.out, "theta_view.png"), *theta_slice, log);
        summary.files.push_back("theta_view.png");
      }
    }
    summary.files.push_back("summary.json");

    summary.bag = args.bag;
    summary.mode = mode.name;
    summary.batch_mode = toString(mode.mode);
    summary.fixed_frame = args.fixed_frame;
    summary.base_frame = args.base_frame;
    summary.input = &input;
    summary.result = &result;
    summary.options = &options;
    summary.batch = &batch;
    summary.wall_seconds = secondsSince(start);
    writeSummaryJson(joinPath(args.out, "summary.json"), summary);

    const double rtf = summary.wall_seconds > 0 ? input.duration / summary.wall_seconds : 0.0;
    log << "mode " << mode.name << ": " << input.scans.size() << " scans in "
        << summary.wall_seconds << " s (" << rtf << "x real time); wrote " << args.out << "/{";
    for (size_t i = 0; i < summary.files.size(); ++i)
      log << (i ? "," : "") << summary.files[i];
    log << "}\n";
    return 0;
  } catch (const InvalidOption& e) {
    log << "rfm_offline: invalid parameter: " << e.what() << "\n";
    return 2;
  } catch (const BagInputError& e) {
    log << "rfm_offline: " << e.what() << "\n";
  } catch (const OutputError& e) {
    log << "rfm_offline: " << e.what() << "\n";
  } catch (const render::PngError& e) {
    log << "rfm_offline: " << e.what() << "\n";
  } catch (const std::exception& e) {
    log << "rfm_offline: failed: " << e.what() << "\n";
  }
  return 1;
}

}  // namespace offline
}  // namespace rfm
