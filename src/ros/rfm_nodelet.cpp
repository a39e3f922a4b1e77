// reflectance_field_map/RfmNodelet: the same MapperRos as rfm_node, inside a nodelet manager.
#include "reflectance_field_map/ros/mapper_ros.h"

#include <nodelet/nodelet.h>
#include <pluginlib/class_list_macros.hpp>

#include <memory>

namespace rfm::ros_glue {

class RfmNodelet : public nodelet::Nodelet {
 private:
  void onInit() override {
    try {
      // getNodeHandle(): single-threaded queue, so this nodelet's callbacks never overlap.
      mapper_ = std::make_unique<MapperRos>(getNodeHandle(), getPrivateNodeHandle());
    } catch (const rfm::InvalidOption& e) {
      NODELET_FATAL("%s", MapperRos::describeParameterError(e).c_str());
      throw;
    } catch (const std::exception& e) {
      NODELET_FATAL("cannot start: %s", e.what());
      throw;
    }
  }

  std::unique_ptr<MapperRos> mapper_;
};

}  // namespace rfm::ros_glue

PLUGINLIB_EXPORT_CLASS(rfm::ros_glue::RfmNodelet, nodelet::Nodelet)
