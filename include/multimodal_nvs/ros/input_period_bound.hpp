#pragma once
// A lower bound on the time between two stamps of one input, learned from the stamps themselves.
// message_filters' ApproximateTime policy forms a set only once it can prove that no later message
// would pair better. Without a bound on when the next message of each input can be stamped, that
// proof needs the next message itself: a set then waits up to one sensor period after its last
// member arrived (measured on a 10 Hz LiDAR with a 15 Hz camera: half of the sets waited 35-38 ms).
// With a bound (the policy's inter-message lower bound) the proof holds as soon as the bound puts
// every possible next message too late, and the same set is published at once.

namespace multimodal_nvs {

class InputPeriodBound {
 public:
  /// The bound is `fraction` of the shortest stamp interval seen, once `min_intervals` intervals
  /// were seen; fraction 0 never gives a bound. A fraction below 1 leaves room for jitter: a
  /// message stamped closer than the bound makes the policy warn once and pair it, possibly not
  /// optimally, and lowers the bound from then on.
  explicit InputPeriodBound(double fraction = 0.9, int min_intervals = 4)
      : fraction_(fraction), min_intervals_(min_intervals) {}

  /// Takes the next message's stamp (seconds); true when the bound changed. Stamps that repeat or
  /// go back (a replayed bag, a reordered message) are no interval and only become the last stamp.
  bool observe(double stamp);

  /// The bound in seconds; 0 while there is none.
  double bound() const { return bound_; }

 private:
  double fraction_;
  int min_intervals_;
  int intervals_ = 0;
  bool has_last_ = false;
  double last_ = 0.0;
  double shortest_ = 0.0;
  double bound_ = 0.0;
};

}  // namespace multimodal_nvs
