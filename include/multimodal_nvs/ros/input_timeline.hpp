#pragma once
// Time bookkeeping of a node's input stream: the order of the processed stamps and the clock it
// runs on. A bag played in a loop restarts both (with --clock, simulated time jumps back; without,
// only the stamps do); a duplicated or reordered message only repeats or reverses one stamp. The
// first must restart the node's state, the second must be dropped.
#include <ros/duration.h>
#include <ros/time.h>

#include "multimodal_nvs/ros/conversions.hpp"

namespace multimodal_nvs {

/// Classifies each stamp against the last accepted one.
class StampOrder {
 public:
  enum class Verdict {
    kNewer,     ///< later than the last accepted stamp (or the first one): process
    kNotNewer,  ///< equal to it or less than `restart_gap` before it: drop
    kRestart,   ///< at least `restart_gap` before it: a restarted stream, process and start over
  };

  /// Out-of-order delivery within one stream spans a synchronizer queue (well below a second);
  /// a replayed bag goes back by its length. The default separates the two for bags of a second
  /// or more.
  explicit StampOrder(ros::Duration restart_gap = ros::Duration(1.0)) : restart_gap_(restart_gap) {}

  /// Verdict for `stamp`; kNewer and kRestart make it the last accepted stamp.
  Verdict check(const ros::Time& stamp) {
    Verdict verdict = Verdict::kNewer;
    if (!last_.isZero() && stamp <= last_) {
      verdict = last_ - stamp < restart_gap_ ? Verdict::kNotNewer : Verdict::kRestart;
    }
    if (verdict != Verdict::kNotNewer) last_ = stamp;
    return verdict;
  }

  /// Forgets the last stamp (after a clock reset every stamp starts over).
  void reset() { last_ = ros::Time(); }
  const ros::Time& last() const { return last_; }

 private:
  ros::Duration restart_gap_;
  ros::Time last_;
};

/// Notices the clock going backwards between two readings (simulated time when a bag played with
/// --clock restarts).
class ClockWatch {
 public:
  /// True when `now` is earlier than the previous reading; `jump` (optional) receives how far.
  bool jumpedBack(const ros::Time& now, ros::Duration* jump = nullptr) {
    const bool back = !last_.isZero() && now < last_;
    if (back && jump) *jump = last_ - now;
    last_ = now;
    return back;
  }

 private:
  ros::Time last_;
};

/// A node's time bookkeeping as one policy: the clock is watched per received message, the stamp
/// order per synchronized set. Either going back far restarts the stream; the node then starts over
/// (clears its synchronizer queues and tf buffer). Not thread-safe: one callback at a time.
class InputTimeline {
 public:
  /// What to do with a set's stamp.
  struct Admission {
    /// The stamps went back by `back`, at least StampOrder's restart gap: a restarted stream (a
    /// bag replayed without --clock). The set is processed; the node starts over first.
    bool restarted = false;
    ros::Duration back;
    /// kStampNotNewer for a repeated or slightly reordered stamp (drop the set), ok otherwise.
    ros_conversions::ConversionStatus status;
  };

  /// Per received message, with the current time: true when the clock went back by `jump` (a bag
  /// restarted with --clock); the stamp history is forgotten then, so the new run's first set is
  /// processed.
  bool clockJumpedBack(const ros::Time& now, ros::Duration* jump = nullptr);

  /// Per synchronized set, with its image stamp.
  Admission admit(const ros::Time& stamp);

 private:
  ClockWatch clock_;
  StampOrder stamps_;
};

}  // namespace multimodal_nvs
