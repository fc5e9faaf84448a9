#pragma once
// An output message that a publisher fills again once everyone else has let go of it.
#include <boost/make_shared.hpp>
#include <boost/shared_ptr.hpp>

namespace multimodal_nvs {

/// Hands out the previous message again when no one else holds it any more, a new one otherwise.
///
/// A full-resolution output is large (9.4 MB of depth at 1936x1216). A new message per frame is a
/// new buffer that the vector zero-fills and the kernel faults in page by page before the
/// conversion writes a single pixel, on the frame's critical path: recycling took the node's
/// median latency on VoD 08350 at full resolution from 41-50 ms to 33-34 ms
/// (scripts/bench_depth_node.sh).
///
/// roscpp drops its reference once it has serialised the message for other processes. A
/// subscriber in the same process (a nodelet) may hold it as long as it likes; then this hands out
/// a new message instead, so nobody ever sees a message change under their feet. Not thread-safe:
/// one publishing thread per instance.
template <class Message>
class RecycledMessage {
 public:
  /// The message to fill and publish next.
  boost::shared_ptr<Message> next() {
    if (!message_ || message_.use_count() > 1) message_ = boost::make_shared<Message>();
    return message_;
  }

 private:
  boost::shared_ptr<Message> message_;
};

}  // namespace multimodal_nvs
