// multimodal_nvs/ConditioningRenderer: the camera image with the depth nodelet's kept depth in;
// conditioning frames (colour, hole mask, depth, camera_info, labelled preview) out, rendered from
// a keyframe into the live camera pose from tf for every camera image, or along a preset
// trajectory as a burst with an optional GEN3C export; the recorded trajectory exported for GEN3C
// through the ~export_trajectory action. Wiring only: what a frame does is
// ros/renderer_session.hpp (conversions in ros/renderer_conversions.hpp, the keyframe policy and
// cloud in ros/renderer_keyframe.hpp, the preset burst in ros/preset_burst.hpp, the recorded
// export in ros/renderer_recorded_export.hpp, the views on tf in ros/renderer_view_frames.hpp,
// rendering in the core's core/render/render_burst.hpp).
#include <actionlib/server/simple_action_server.h>
#include <dynamic_reconfigure/server.h>
#include <image_transport/image_transport.h>
#include <multimodal_nvs/ExportTrajectoryAction.h>
#include <nodelet/nodelet.h>
#include <std_srvs/Trigger.h>
#include <tf2_eigen/tf2_eigen.h>
#include <tf2_ros/buffer.h>
#include <tf2_ros/static_transform_broadcaster.h>
#include <tf2_ros/transform_listener.h>
#include <pluginlib/class_list_macros.hpp>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <condition_variable>
#include <deque>
#include <memory>
#include <mutex>
#include <thread>

#include "conditioning_renderer_diagnostics.hpp"
#include "conditioning_renderer_inputs.hpp"
#include "conditioning_renderer_outputs.hpp"
#include "multimodal_nvs/core/common/elapsed.hpp"
#include "multimodal_nvs/ros/preset_burst.hpp"
#include "multimodal_nvs/ros/renderer_conversions.hpp"
#include "multimodal_nvs/ros/renderer_recorded_export.hpp"
#include "multimodal_nvs/ros/renderer_session.hpp"
#include "multimodal_nvs/ros/renderer_view_frames.hpp"
#include "nodelet_state.hpp"

namespace multimodal_nvs {

namespace rc = ros_conversions;

class ConditioningRendererNodelet : public nodelet::Nodelet {
 private:
  using Config = ConditioningRendererConfig;
  using Settings = ConditioningRendererSettings;
  using ExportServer = actionlib::SimpleActionServer<ExportTrajectoryAction>;

 public:
  ~ConditioningRendererNodelet() override;

 private:
  void onInit() override;
  void connectCb();
  void onCameraImage(const sensor_msgs::ImageConstPtr& image);
  /// The live-view thread: serves the camera images and depth sets the callbacks queued, in their
  /// order, rendering only the newest max_live_backlog of the camera images waiting (the others
  /// are recorded for the export, counted as skipped).
  void serveInputs();
  void onFrame(const sensor_msgs::ImageConstPtr& image, const sensor_msgs::ImageConstPtr& depth,
               const sensor_msgs::ImageConstPtr& mask, const sensor_msgs::CameraInfoConstPtr& info);
  rc::RendererStatus lookupCameraPose(const std::string& world_frame,
                                      const std_msgs::Header& header,
                                      Eigen::Matrix4d& camera_to_world);
  bool onSetKeyframe(std_srvs::Trigger::Request&, std_srvs::Trigger::Response& res);
  bool onRender(std_srvs::Trigger::Request&, std_srvs::Trigger::Response& res);
  void onExportGoal(const ExportTrajectoryGoalConstPtr& goal);
  void exportPreset(const ExportTrajectoryGoal& goal);
  void exportRecorded(const ExportTrajectoryGoal& goal);
  /// Waits for the session's collection; true with `job` filled once it is complete, false after
  /// reporting (result sent, counted) a cancel, a timeout or an abort.
  bool collectRecordedPoses(const ExportTrajectoryGoal& goal, RecordedExportJob& job);
  void endExport(ConditioningRendererDiagnostics::ExportEnd end, const std::string& message,
                 const ExportTrajectoryResult& result);
  void publishViews(const Trajectory& views, const std_msgs::Header& keyframe_header,
                    const std::optional<Eigen::Matrix4d>& keyframe_in_world,
                    const std::string& world_frame);
  void count(const RendererStep& step);
  void reconfigure(Config& config, uint32_t level);

  // Static parameters (read once in onInit).
  int queue_size_ = 5;
  int camera_queue_size_ = 30;
  int publisher_queue_size_ = 10;
  int max_live_backlog_ = 8;
  // How long an input may wait, counted from its arrival, for tf to reach its stamp: a bag or a
  // driver often publishes the camera image before the /tf that holds its pose. Counted from the
  // arrival (not from the lookup) so that the images queued behind a missing transform wait with
  // it, not one timeout after another.
  std::chrono::steady_clock::duration tf_timeout_{};
  std::chrono::steady_clock::time_point pose_deadline_;  // of the input being served; state_mutex_

  // Inputs (exact-time sync), subscribed only while an output has a subscriber or a preset burst
  // is exported.
  std::unique_ptr<image_transport::ImageTransport> it_;
  std::unique_ptr<ConditioningRendererInputs> inputs_;

  // Outputs. connect_mutex_ also guards their assignment: connect callbacks may fire meanwhile.
  std::mutex connect_mutex_;
  bool advertised_ = false;
  bool subscribed_ = false;
  ConditioningRendererOutputs outputs_;
  ros::ServiceServer set_keyframe_srv_, render_srv_;

  std::unique_ptr<tf2_ros::Buffer> tf_buffer_;
  std::unique_ptr<tf2_ros::TransformListener> tf_listener_;
  std::unique_ptr<tf2_ros::StaticTransformBroadcaster> view_broadcaster_;
  ros::Publisher trajectory_pub_;  // conditioning/trajectory (latched PoseArray of the views)

  // ~export_trajectory: its goals run on the action server's thread, one at a time, with their
  // own engine; export_active_ keeps the inputs subscribed while a collection runs.
  std::unique_ptr<ExportServer> export_server_;
  ThreadCountCached<PointSplatter> export_splatter_;
  std::atomic<bool> export_active_{false};
  std::atomic<bool> shutting_down_{false};

  // Written by the reconfigure callback, copied once per frame by the frame callback.
  GuardedSettings<Settings> settings_;
  std::unique_ptr<dynamic_reconfigure::Server<Config>> reconfigure_server_;
  boost::recursive_mutex reconfigure_mutex_;

  // Camera images and depth sets waiting for the live-view thread, in arrival order. The
  // subscriber callbacks only queue them, so ROS's own queues never overflow while a frame
  // renders or a keyframe is built (a dropped image would also be a pose the recorded export
  // never gets). An entry with depth is a synchronized set, one without a camera image.
  struct PendingInput {
    sensor_msgs::ImageConstPtr image, depth, mask;
    sensor_msgs::CameraInfoConstPtr info;
    std::chrono::steady_clock::time_point arrival;
  };
  /// Queues `input`; when the oldest camera image has to make room, counts and logs the drop.
  void enqueue(PendingInput input);
  std::mutex pending_mutex_;
  std::condition_variable pending_cv_;
  std::deque<PendingInput> pending_;
  bool stop_input_thread_ = false;
  std::thread input_thread_;

  // Keyframe and renderer, shared by the frame callback, the live-view thread and the services.
  std::mutex state_mutex_;
  std::unique_ptr<RendererSession> session_;
  ThreadCountCached<PointSplatter> splatter_;
  PerFaultLogThrottle<rc::kRendererFaultCount> log_throttle_;
  ConditioningRendererDiagnostics diagnostics_;
};

void ConditioningRendererNodelet::onInit() {
  ros::NodeHandle& nh = getNodeHandle();
  ros::NodeHandle& pnh = getPrivateNodeHandle();
  queue_size_ = pnh.param("queue_size", 5);
  camera_queue_size_ = pnh.param("camera_queue_size", 30);
  publisher_queue_size_ = pnh.param("publisher_queue_size", 10);
  max_live_backlog_ = std::max(1, pnh.param("max_live_backlog", 8));
  tf_timeout_ = std::chrono::duration_cast<std::chrono::steady_clock::duration>(
      std::chrono::duration<double>(std::max(0.0, pnh.param("tf_timeout", 0.5))));

  tf_buffer_ = std::make_unique<tf2_ros::Buffer>();
  tf_listener_ = std::make_unique<tf2_ros::TransformListener>(*tf_buffer_, nh);
  diagnostics_.start(nh, pnh, getName());
  session_ = std::make_unique<RendererSession>(RendererSessionIo{
      [this](const std::string& world_frame, const std_msgs::Header& header,
             Eigen::Matrix4d& pose) { return lookupCameraPose(world_frame, header, pose); },
      [this](int threads) -> PointSplatter& { return splatter_.forThreads(threads); },
      [this](const RenderedFrame& frame, const PinholeIntrinsics& intrinsics, const ImageSize& size,
             const std_msgs::Header& header) { outputs_.publish(frame, intrinsics, size, header); },
      [this](const Trajectory& views, const std_msgs::Header& keyframe_header) {
        publishViews(views, keyframe_header, std::nullopt, "");
      }});
  view_broadcaster_ = std::make_unique<tf2_ros::StaticTransformBroadcaster>();
  trajectory_pub_ = nh.advertise<geometry_msgs::PoseArray>("conditioning/trajectory", 1, true);

  // The .cfg defaults first; the server then applies the parameter server (YAML) through the same
  // mapping and subscribes the inputs if the settings alone want them (an exported preset).
  settings_.set(rendererSettingsFromConfig(Config::__getDefault__()));
  it_ = std::make_unique<image_transport::ImageTransport>(nh);
  inputs_ = std::make_unique<ConditioningRendererInputs>(
      queue_size_,
      boost::bind(&ConditioningRendererNodelet::onFrame, this, boost::placeholders::_1,
                  boost::placeholders::_2, boost::placeholders::_3, boost::placeholders::_4),
      boost::bind(&ConditioningRendererNodelet::onCameraImage, this, boost::placeholders::_1));
  {
    std::lock_guard<std::mutex> lock(connect_mutex_);
    const image_transport::SubscriberStatusCallback image_cb =
        boost::bind(&ConditioningRendererNodelet::connectCb, this);
    const ros::SubscriberStatusCallback info_cb =
        boost::bind(&ConditioningRendererNodelet::connectCb, this);
    outputs_.advertise(*it_, static_cast<uint32_t>(std::max(1, publisher_queue_size_)), image_cb,
                       info_cb);
    advertised_ = true;
  }
  reconfigure_server_ =
      std::make_unique<dynamic_reconfigure::Server<Config>>(reconfigure_mutex_, pnh);
  reconfigure_server_->setCallback(boost::bind(&ConditioningRendererNodelet::reconfigure, this,
                                               boost::placeholders::_1, boost::placeholders::_2));
  set_keyframe_srv_ =
      pnh.advertiseService("set_keyframe", &ConditioningRendererNodelet::onSetKeyframe, this);
  render_srv_ = pnh.advertiseService("render", &ConditioningRendererNodelet::onRender, this);
  export_server_ = std::make_unique<ExportServer>(
      pnh, "export_trajectory",
      boost::bind(&ConditioningRendererNodelet::onExportGoal, this, boost::placeholders::_1),
      false);
  export_server_->start();
  input_thread_ = std::thread(&ConditioningRendererNodelet::serveInputs, this);
}

ConditioningRendererNodelet::~ConditioningRendererNodelet() {
  shutting_down_ = true;  // a running goal sees it at its next check and ends
  if (export_server_) export_server_->shutdown();
  {
    std::lock_guard<std::mutex> lock(pending_mutex_);
    stop_input_thread_ = true;
  }
  pending_cv_.notify_all();
  if (input_thread_.joinable()) input_thread_.join();
}

// Lazy subscription (depth_image_proc's idiom): inputs follow the presence of output subscribers,
// or of a preset burst that is exported to disk.
void ConditioningRendererNodelet::connectCb() {
  std::lock_guard<std::mutex> lock(connect_mutex_);
  if (!advertised_) return;
  const bool wanted =
      presetExportWanted(settings_.get()) || export_active_ || outputs_.anySubscribed();
  if (wanted && !subscribed_) {
    inputs_->subscribe(*it_, getNodeHandle(), getPrivateNodeHandle(),
                       static_cast<uint32_t>(std::max(1, camera_queue_size_)));
  }
  if (!wanted && subscribed_) inputs_->unsubscribe();
  subscribed_ = wanted;
  diagnostics_.setSubscribed(wanted);
}

void ConditioningRendererNodelet::enqueue(PendingInput input) {
  bool dropped = false;
  {
    std::lock_guard<std::mutex> lock(pending_mutex_);
    pending_.push_back(std::move(input));
    // Bounded like the session's history: a thread stalled this long has lost the live view.
    // Depth sets stay (each may be a keyframe); the oldest camera image goes.
    if (pending_.size() > RendererSession::kHistoryFrames) {
      const auto oldest_image = std::find_if(pending_.begin(), pending_.end(),
                                             [](const PendingInput& p) { return !p.depth; });
      if (oldest_image != pending_.end()) {
        pending_.erase(oldest_image);
        dropped = true;
      }
    }
  }
  pending_cv_.notify_one();
  if (dropped) {
    diagnostics_.countCameraImageDropped();
    NODELET_ERROR_THROTTLE(2.0, "camera image dropped: %zu inputs wait for the live view",
                           RendererSession::kHistoryFrames);
  }
}

void ConditioningRendererNodelet::onCameraImage(const sensor_msgs::ImageConstPtr& image) {
  diagnostics_.countCameraImage();
  enqueue({image, nullptr, nullptr, nullptr, std::chrono::steady_clock::now()});
}

void ConditioningRendererNodelet::onFrame(const sensor_msgs::ImageConstPtr& image,
                                          const sensor_msgs::ImageConstPtr& depth,
                                          const sensor_msgs::ImageConstPtr& mask,
                                          const sensor_msgs::CameraInfoConstPtr& info) {
  diagnostics_.countSet();
  enqueue({image, depth, mask, info, std::chrono::steady_clock::now()});
}

void ConditioningRendererNodelet::serveInputs() {
  for (;;) {
    std::deque<PendingInput> batch;
    {
      std::unique_lock<std::mutex> lock(pending_mutex_);
      pending_cv_.wait(lock, [this] { return stop_input_thread_ || !pending_.empty(); });
      if (stop_input_thread_) return;
      batch.swap(pending_);
    }
    // Only the newest max_live_backlog_ camera images of the batch are rendered live.
    std::size_t images_after = 0;
    std::vector<bool> render(batch.size(), false);
    for (std::size_t i = batch.size(); i-- > 0;) {
      if (batch[i].depth) continue;
      render[i] = images_after < static_cast<std::size_t>(max_live_backlog_);
      ++images_after;
    }
    const Settings settings = settings_.get();
    std::lock_guard<std::mutex> lock(state_mutex_);
    for (std::size_t i = 0; i < batch.size(); ++i) {
      const PendingInput& in = batch[i];
      pose_deadline_ = in.arrival + tf_timeout_;
      if (!in.depth) {
        count(session_->onCameraImage(*in.image, settings, in.arrival, render[i]));
        continue;
      }
      const RendererStep step =
          session_->onInputSet(*in.image, *in.depth, *in.mask, *in.info, settings, in.arrival);
      count(step);
      if (!step.error.empty()) NODELET_ERROR_THROTTLE(2.0, "%s", step.error.c_str());
    }
  }
}

rc::RendererStatus ConditioningRendererNodelet::lookupCameraPose(const std::string& world_frame,
                                                                 const std_msgs::Header& header,
                                                                 Eigen::Matrix4d& camera_to_world) {
  const double wait_s = std::max(
      0.0,
      std::chrono::duration<double>(pose_deadline_ - std::chrono::steady_clock::now()).count());
  try {
    camera_to_world =
        tf2::transformToEigen(tf_buffer_->lookupTransform(world_frame, header.frame_id,
                                                          header.stamp, ros::Duration(wait_s)))
            .matrix();
    return rc::RendererStatus::success();
  } catch (const tf2::TransformException& e) {
    return rc::RendererStatus::failure(
        rc::RendererFault::kTransformUnavailable,
        "tf " + world_frame + " -> '" + header.frame_id + "': " + e.what());
  }
}

bool ConditioningRendererNodelet::onSetKeyframe(std_srvs::Trigger::Request&,
                                                std_srvs::Trigger::Response& res) {
  session_->requestKeyframe();
  res.success = true;
  res.message = "the next synchronized input set becomes the keyframe";
  bool subscribed;
  {
    std::lock_guard<std::mutex> lock(connect_mutex_);
    subscribed = subscribed_;
  }
  if (!subscribed) res.message += " (inputs are not subscribed yet: no output has a subscriber)";
  return true;
}

bool ConditioningRendererNodelet::onRender(std_srvs::Trigger::Request&,
                                           std_srvs::Trigger::Response& res) {
  const Settings settings = settings_.get();
  std::lock_guard<std::mutex> lock(state_mutex_);
  const RendererStep step = session_->renderBurst(settings);
  count(step);
  res.success = step.burst;
  res.message = step.burst ? step.report : step.error;
  if (!res.success) NODELET_ERROR("~render: %s", res.message.c_str());
  return true;
}

/// Counts and logs what a step did; a rejected input set is logged throttled per reason (so that
/// one recurring fault does not hide another). Called with state_mutex_ held.
void ConditioningRendererNodelet::count(const RendererStep& step) {
  std::vector<rc::RendererStatus> faults = step.frame_faults;
  faults.push_back(step.fault);
  for (const rc::RendererStatus& fault : faults) {
    if (fault.ok()) continue;
    diagnostics_.countFault(fault.fault);
    if (log_throttle_.due(fault.fault)) {
      NODELET_ERROR("dropping input: %s [%s]", fault.reason.c_str(), rc::toString(fault.fault));
    }
  }
  if (step.keyframe) {
    diagnostics_.countKeyframe(step.keyframe_points, step.keyframe_ms);
    NODELET_DEBUG("keyframe at %.3f: %zu points", step.keyframe_stamp.toSec(),
                  step.keyframe_points);
  }
  if (step.live_skipped > 0) diagnostics_.countLiveSkipped(step.live_skipped);
  for (const RendererStep::LiveFrame& frame : step.live_frames) {
    diagnostics_.countFrame(frame.render_ms, frame.frame_ms);
  }
  if (!step.warning.empty()) NODELET_WARN_ONCE("%s", step.warning.c_str());
  if (step.burst) {
    diagnostics_.countBurst(step.burst_frames, step.burst_ms);
    NODELET_INFO("%s", step.report.c_str());
  }
}

void ConditioningRendererNodelet::onExportGoal(const ExportTrajectoryGoalConstPtr& goal) {
  if (goal->trajectory == "preset") {
    exportPreset(*goal);
  } else if (goal->trajectory.empty() || goal->trajectory == "recorded") {
    exportRecorded(*goal);
  } else {
    ExportTrajectoryResult result;
    endExport(ConditioningRendererDiagnostics::ExportEnd::kFailed,
              "unknown trajectory '" + goal->trajectory + "' (recorded | preset)", result);
  }
}

/// The preset burst of ~render with the goal's frame count and folder; one step, so its feedback
/// is its start and its end, and a cancel takes effect after it.
void ConditioningRendererNodelet::exportPreset(const ExportTrajectoryGoal& goal) {
  Settings settings = settings_.get();
  if (goal.num_frames > 0) settings.num_frames = goal.num_frames;
  if (!goal.output_dir.empty()) settings.export_dir = goal.output_dir;
  ExportTrajectoryFeedback feedback;
  feedback.stage = "rendering";
  feedback.total = settings.num_frames;
  export_server_->publishFeedback(feedback);
  RendererStep step;
  {
    std::lock_guard<std::mutex> lock(state_mutex_);
    step = session_->renderBurst(settings);
    count(step);
  }
  ExportTrajectoryResult result;
  result.frames = step.burst ? step.burst_frames : 0;
  if (!step.burst) {
    endExport(ConditioningRendererDiagnostics::ExportEnd::kFailed, step.error, result);
    return;
  }
  feedback.done = step.burst_frames;
  export_server_->publishFeedback(feedback);
  result.success = true;
  result.message = step.report;
  const std::string marker = "GEN3C folder ";
  const std::size_t at = step.report.find(marker);
  if (at != std::string::npos) result.folder = step.report.substr(at + marker.size());
  export_server_->setSucceeded(result, result.message);
}

void ConditioningRendererNodelet::exportRecorded(const ExportTrajectoryGoal& goal) {
  using End = ConditioningRendererDiagnostics::ExportEnd;
  const auto start = std::chrono::steady_clock::now();
  RecordedExportJob job;
  if (!collectRecordedPoses(goal, job)) return;

  ExportTrajectoryFeedback feedback;
  feedback.stage = "rendering";
  const auto rendering = std::chrono::steady_clock::now();
  const RecordedExportResult exported = exportRecordedTrajectory(
      export_splatter_.forThreads(job.settings.threads), job,
      [this, &feedback](int done, int total) {
        feedback.done = done;
        feedback.total = total;
        export_server_->publishFeedback(feedback);
      },
      [this] { return shutting_down_ || export_server_->isPreemptRequested(); });
  ExportTrajectoryResult result;
  result.poses = static_cast<int>(job.poses.stamps.size());
  if (!exported.ok) {
    endExport(exported.cancelled ? End::kCancelled : End::kFailed, exported.error, result);
    return;
  }
  publishViews(exported.trajectory, job.keyframe.header, job.poses.camera_to_world.front(),
               job.settings.world_frame);
  result.success = true;
  result.folder = exported.folder;
  result.frames = job.poses.request.num_frames;
  const double ms = millisecondsSince(start), render_ms = millisecondsSince(rendering);
  char message[200];
  // Rendering and writing apart from the whole goal: collecting waits for the camera.
  std::snprintf(message, sizeof message,
                "%d recorded poses rendered and written as %d frames in %.0f ms (%.0f ms since "
                "the goal)",
                result.poses, result.frames, render_ms, ms);
  result.message = std::string(message) + "; folder " + exported.folder;
  diagnostics_.countExport(End::kComplete, result.frames, render_ms);
  NODELET_INFO("~export_trajectory: %s", result.message.c_str());
  export_server_->setSucceeded(result, result.message);
}

bool ConditioningRendererNodelet::collectRecordedPoses(const ExportTrajectoryGoal& goal,
                                                       RecordedExportJob& job) {
  using End = ConditioningRendererDiagnostics::ExportEnd;
  using Stage = RecordedPoseCollector::Stage;
  const Settings settings = settings_.get();
  RecordedExportRequest request;
  request.num_poses = goal.num_poses;
  request.duration = goal.duration;
  request.num_frames = goal.num_frames > 0 ? goal.num_frames : settings.num_frames;
  request.output_dir = goal.output_dir.empty() ? settings.export_dir : goal.output_dir;
  ExportTrajectoryResult result;
  {
    std::lock_guard<std::mutex> lock(state_mutex_);
    if (const auto error = session_->startExport(request)) {
      endExport(End::kFailed, *error, result);
      return false;
    }
  }
  export_active_ = true;
  connectCb();
  const ros::WallTime deadline = ros::WallTime::now() + ros::WallDuration(goal.timeout);
  std::string abort_reason;
  End end = End::kAborted;
  bool complete = false;
  ExportTrajectoryFeedback feedback;
  while (!complete && abort_reason.empty()) {
    {
      std::lock_guard<std::mutex> lock(state_mutex_);
      if (shutting_down_ || !ros::ok() || export_server_->isPreemptRequested()) {
        session_->abortExport("cancelled while waiting for or collecting the recorded poses");
        end = End::kCancelled;
      } else if (goal.timeout > 0.0 && ros::WallTime::now() > deadline) {
        session_->abortExport("timed out after " + std::to_string(goal.timeout) +
                              " s of wall time (no keyframe, or too few camera frames)");
      }
      const RecordedPoseCollector& collector = session_->exportCollector();
      if (collector.stage() == Stage::kComplete) {
        complete = session_->takeExportJob(settings_.get(), job);
      }
      if (collector.stage() == Stage::kAborted) {
        abort_reason = collector.abortReason();
        session_->resetExport();
      }
      feedback.stage =
          collector.stage() == Stage::kCollecting ? "collecting" : "waiting_for_keyframe";
      feedback.done = collector.collected();
      feedback.total = request.duration > 0.0 ? 0 : request.num_poses;
    }
    if (!complete && abort_reason.empty()) {
      export_server_->publishFeedback(feedback);
      ros::WallDuration(0.05).sleep();
    }
  }
  export_active_ = false;
  connectCb();
  if (complete) return true;
  endExport(end, abort_reason, result);
  return false;
}

/// Reports an export that did not complete: counted, logged throttled, and the goal preempted
/// (a cancel) or aborted.
void ConditioningRendererNodelet::endExport(ConditioningRendererDiagnostics::ExportEnd end,
                                            const std::string& message,
                                            const ExportTrajectoryResult& partial) {
  diagnostics_.countExport(end, 0, 0.0);
  ExportTrajectoryResult result = partial;
  result.success = false;
  result.message = message;
  NODELET_ERROR_THROTTLE(2.0, "~export_trajectory: %s", message.c_str());
  if (end == ConditioningRendererDiagnostics::ExportEnd::kCancelled) {
    export_server_->setPreempted(result, message);
  } else {
    export_server_->setAborted(result, message);
  }
}

void ConditioningRendererNodelet::publishViews(
    const Trajectory& views, const std_msgs::Header& keyframe_header,
    const std::optional<Eigen::Matrix4d>& keyframe_in_world, const std::string& world_frame) {
  const std::vector<geometry_msgs::TransformStamped> transforms =
      virtualViewTransforms(views, keyframe_header, keyframe_in_world, world_frame);
  view_broadcaster_->sendTransform(transforms);
  trajectory_pub_.publish(viewPoseArray(transforms));
}

void ConditioningRendererNodelet::reconfigure(Config& config, uint32_t /*level*/) {
  if (const auto error = settings_.reconfigure(config, rendererSettingsFromConfig,
                                               writeRendererSettingsToConfig)) {
    NODELET_ERROR("rejected parameter update (%s); keeping the previous values", error->c_str());
  }
  connectCb();  // trajectory_source and export_dir decide whether the inputs are needed
}

}  // namespace multimodal_nvs

PLUGINLIB_EXPORT_CLASS(multimodal_nvs::ConditioningRendererNodelet, nodelet::Nodelet)
