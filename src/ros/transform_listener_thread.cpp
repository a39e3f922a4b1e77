#include "reflectance_field_map/ros/transform_listener_thread.h"

namespace rfm::ros_glue {

TransformListenerThread::TransformListenerThread(tf2_ros::Buffer& buffer, const ros::NodeHandle& nh,
                                                 double idle_wait)
    : nh_(nh) {
  nh_.setCallbackQueue(&queue_);
  listener_ = std::make_unique<tf2_ros::TransformListener>(buffer, nh_, /*spin_thread=*/false);
  thread_ = std::thread([this, idle_wait] {
    // callAvailable returns as soon as a callback is queued: a transform waits for nothing.
    while (running_.load(std::memory_order_acquire) && nh_.ok())
      queue_.callAvailable(ros::WallDuration(idle_wait));
  });
}

TransformListenerThread::~TransformListenerThread() {
  running_.store(false, std::memory_order_release);
  thread_.join();
  listener_.reset();  // unsubscribes: nothing more is queued
  queue_.clear();
}

}  // namespace rfm::ros_glue
