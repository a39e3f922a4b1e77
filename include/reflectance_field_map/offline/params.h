#pragma once

#include "reflectance_field_map/core/options.h"

#include <stdexcept>
#include <string>
#include <vector>

namespace rfm {
namespace offline {

// The parameters file can't be read (missing, not YAML): what() names the file.
class ParamsError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

struct ParamsReport {
  std::vector<std::string> applied;  // option names set from the file
  std::vector<std::string> ignored;  // keys that are not options (e.g. topic names)
};

// Sets every mapper and batch option found in a YAML file through the option tables
// (optionFields(), batchOptionFields(), setOption()). Options may sit at the top level or inside
// nested maps (a node namespace, a group), so config/*.yaml files of the node load as they are.
// Values are numbers or booleans. Throws ParamsError when the file can't be read or parsed,
// InvalidOption (naming the parameter) when an option's value is not a number or a boolean.
// Ranges are checked by the structs' validate(), which the caller runs after all overrides.
ParamsReport loadParamsFile(const std::string& path, MapperOptions& options, BatchOptions& batch);
// The mapper's options only (a live mapper): batch keys are reported ignored.
ParamsReport loadParamsFile(const std::string& path, MapperOptions& options);
// Same for YAML text (tests); `source` names it in messages.
ParamsReport loadParamsText(const std::string& yaml, MapperOptions& options, BatchOptions& batch,
                            const std::string& source = "<text>");
ParamsReport loadParamsText(const std::string& yaml, MapperOptions& options,
                            const std::string& source = "<text>");

}  // namespace offline
}  // namespace rfm
