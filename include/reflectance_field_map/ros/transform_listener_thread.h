#pragma once

#include <ros/callback_queue.h>
#include <ros/node_handle.h>
#include <tf2_ros/buffer.h>
#include <tf2_ros/transform_listener.h>

#include <atomic>
#include <memory>
#include <thread>

namespace rfm::ros_glue {

// Fills a tf2 buffer from /tf and /tf_static on a thread of its own, as
// tf2_ros::TransformListener's dedicated thread does, but wakes only when a transform arrives
// (or every `idle_wait` s): tf2's thread looks at its queue 100 times a second whether or not
// anything came, which is most of an idle node's CPU.
class TransformListenerThread {
 public:
  TransformListenerThread(tf2_ros::Buffer& buffer, const ros::NodeHandle& nh,
                          double idle_wait = 0.1);
  // Stops the thread: no transform is added to the buffer after this returns.
  ~TransformListenerThread();

  TransformListenerThread(const TransformListenerThread&) = delete;
  TransformListenerThread& operator=(const TransformListenerThread&) = delete;

 private:
  ros::CallbackQueue queue_;
  ros::NodeHandle nh_;  // the caller's namespace, its callbacks on queue_
  std::unique_ptr<tf2_ros::TransformListener> listener_;
  std::atomic<bool> running_{true};
  std::thread thread_;
};

}  // namespace rfm::ros_glue
