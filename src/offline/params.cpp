#include "reflectance_field_map/offline/params.h"

#include <yaml-cpp/yaml.h>

#include <fstream>
#include <sstream>

namespace rfm {
namespace offline {
namespace {

bool isField(const std::vector<OptionField>& table, const std::string& name) {
  for (const OptionField& field : table) {
    if (field.name == name) return true;
  }
  return false;
}

double scalarValue(const std::string& name, const YAML::Node& node) {
  if (!node.IsScalar()) {
    throw InvalidOption(name, node.IsNull() ? "(empty)" : "(a YAML map or list)",
                        "a number or a boolean");
  }
  try {
    return node.as<double>();
  } catch (const YAML::Exception&) {
  }
  try {
    return node.as<bool>() ? 1.0 : 0.0;
  } catch (const YAML::Exception&) {
  }
  throw InvalidOption(name, "'" + node.Scalar() + "'", "a number or a boolean");
}

// `batch` may be null: batch keys are then ignored.
void visit(const YAML::Node& node, const std::string& path, MapperOptions& options,
           BatchOptions* batch, ParamsReport& report) {
  for (const auto& entry : node) {
    const std::string key = entry.first.as<std::string>();
    const std::string full = path.empty() ? key : path + "/" + key;
    const YAML::Node& value = entry.second;
    if (isField(optionFields(), key)) {
      setOption(options, key, scalarValue(key, value));
      report.applied.push_back(key);
    } else if (batch && isField(batchOptionFields(), key)) {
      setOption(*batch, key, scalarValue(key, value));
      report.applied.push_back(key);
    } else if (value.IsMap()) {
      visit(value, full, options, batch, report);
    } else {
      report.ignored.push_back(full);
    }
  }
}

ParamsReport loadText(const std::string& yaml, MapperOptions& options, BatchOptions* batch,
                      const std::string& source) {
  YAML::Node root;
  try {
    root = YAML::Load(yaml);
  } catch (const YAML::Exception& e) {
    throw ParamsError("cannot parse parameters " + source + ": " + e.what());
  }
  ParamsReport report;
  if (root.IsNull()) return report;  // empty file
  if (!root.IsMap()) {
    throw ParamsError("parameters " + source + " must be a YAML map of name: value");
  }
  visit(root, "", options, batch, report);
  return report;
}

std::string fileText(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw ParamsError("cannot read parameters file " + path);
  std::ostringstream text;
  text << in.rdbuf();
  return text.str();
}

}  // namespace

ParamsReport loadParamsText(const std::string& yaml, MapperOptions& options, BatchOptions& batch,
                            const std::string& source) {
  return loadText(yaml, options, &batch, source);
}

ParamsReport loadParamsText(const std::string& yaml, MapperOptions& options,
                            const std::string& source) {
  return loadText(yaml, options, nullptr, source);
}

ParamsReport loadParamsFile(const std::string& path, MapperOptions& options, BatchOptions& batch) {
  return loadText(fileText(path), options, &batch, path);
}

ParamsReport loadParamsFile(const std::string& path, MapperOptions& options) {
  return loadText(fileText(path), options, nullptr, path);
}

}  // namespace offline
}  // namespace rfm
