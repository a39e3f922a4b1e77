// rfm_offline: the Reflectance Field Map of a whole bag (see --help).

#include "reflectance_field_map/offline/arguments.h"
#include "reflectance_field_map/offline/offline_tool.h"

#include <iostream>

int main(int argc, char** argv) {
  rfm::offline::OfflineArguments args;
  try {
    args = rfm::offline::parseArguments(argc, argv);
  } catch (const rfm::offline::ArgumentError& e) {
    std::cerr << "rfm_offline: " << e.what() << "\n\n" << rfm::offline::usage();
    return 2;
  }
  if (args.help) {
    std::cout << rfm::offline::usage();
    return 0;
  }
  return rfm::offline::runOffline(args, std::cerr);
}
