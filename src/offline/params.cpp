#include "reflectance_field_map/offline/params.h"

#include <yaml-cpp/yaml.h>

#include <fstream>
#include <sstream>

namespace rfm {
namespace offline {
namespace {

const OptionField* findField(const std::string& name) {
  for (const OptionField& field : optionFields()) {
    if (field.name == name) return &field;
  }
  return nullptr;
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

void visit(const YAML::Node& node, const std::string& path, MapperOptions& options,
           ParamsReport& report) {
  for (const auto& entry : node) {
    const std::string key = entry.first.as<std::string>();
    const std::string full = path.empty() ? key : path + "/" + key;
    const YAML::Node& value = entry.second;
    if (const OptionField* field = findField(key)) {
      setOption(options, field->name, scalarValue(field->name, value));
      report.applied.push_back(field->name);
    } else if (value.IsMap()) {
      visit(value, full, options, report);
    } else {
      report.ignored.push_back(full);
    }
  }
}

}  // namespace

ParamsReport loadParamsText(const std::string& yaml, MapperOptions& options,
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
  visit(root, "", options, report);
  return report;
}

ParamsReport loadParamsFile(const std::string& path, MapperOptions& options) {
  std::ifstream in(path);
  if (!in) throw ParamsError("cannot read parameters file " + path);
  std::ostringstream text;
  text << in.rdbuf();
  return loadParamsText(text.str(), options, path);
}

}  // namespace offline
}  // namespace rfm
