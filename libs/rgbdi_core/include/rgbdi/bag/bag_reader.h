// Streaming reader of ROS1 bags (format 2.0) that survives damage.
//
// A healthy bag is read with Debian's rosbag storage library (rosbag::View, bag-time order, only
// the requested topics). A bag whose index cannot be read (a truncated copy loses it, because the
// index sits at the end of the file; an interrupted recording never wrote it) is read instead by
// scanning its chunks in file order ("recovery mode"): every message up to the damage is still
// delivered. Damage met while reading (corrupt chunk, the file ending inside a chunk) ends the
// stream with a BagReadError naming the file and the position; everything before it has been
// delivered. Memory: one decompressed chunk plus one message at a time. rosbag allocates by the
// size fields it reads, so the record structure is checked first (bag_structure_check.h): a
// corrupt size is refused with the byte offset, never an abort or gigabytes allocated.
#pragma once

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "rgbdi/bag/bag_writer.h"

namespace rgbdi::bag {

/// Damage found while reading messages; what() names the file and the position.
class BagReadError : public BagError {
 public:
  using BagError::BagError;
};

/// Sizes above which a bag's record is taken for corruption, checked before anything is
/// allocated by them (rosbag_storage asserts when such an allocation fails).
struct BagLimits {
  std::uint32_t max_record_header_bytes = 1u << 20;  ///< [bytes] a few short fields in practice
  /// [bytes] a chunk, decompressed or stored (rosbag records 768 KiB chunks by default)
  std::uint32_t max_chunk_bytes = 1u << 30;
};

/// One topic of the bag (connections with the same topic merged).
struct BagTopic {
  std::string topic;
  std::string datatype;  ///< e.g. "sensor_msgs/Image"
  std::uint64_t messages = 0;
  std::string md5sum;  ///< of the message definition (the first connection's)
};

/// One serialized message (ROS wire format), valid until the next call to BagReader::next().
struct BagMessage {
  const std::string* topic = nullptr;
  const std::string* datatype = nullptr;
  double bag_time = 0.0;  ///< time recorded by the bag writer [s]
  const std::uint8_t* data = nullptr;
  std::uint32_t size = 0;
  std::uint64_t ordinal = 0;  ///< 0-based number of the message in this stream
  std::uint64_t position =
      0;  ///< byte offset of the record holding it (recovery mode; 0 otherwise)
};

class BagReader {
 public:
  /// Opens `path` and reads its index (or, in recovery mode, pre-scans its chunks for the
  /// topics). next() delivers messages of `topics` only (all when empty). Throws BagError when the
  /// file cannot be opened or is not a ROS1 2.0 bag. The record structure is checked against
  /// the file size and `limits` before rosbag reads the index; a bag that fails the check is
  /// read in recovery mode (recoveryReason() names the byte offset and the problem).
  explicit BagReader(const std::string& path, const std::vector<std::string>& topics = {},
                     const BagLimits& limits = {});
  ~BagReader();
  BagReader(const BagReader&) = delete;
  BagReader& operator=(const BagReader&) = delete;

  const std::string& path() const { return path_; }
  /// False in recovery mode; recoveryReason() then says why the index was unusable.
  bool indexed() const;
  const std::string& recoveryReason() const;
  /// Where the readable data ends in recovery mode ("" when the whole file is readable).
  const std::string& damage() const;

  /// Every topic of the bag, sorted by name, with type and message count.
  const std::vector<BagTopic>& topics() const;
  /// Bag time of the first and last message of the whole bag [s] (0 when empty).
  double beginTime() const;
  double endTime() const;
  std::uint64_t fileSize() const;

  /// Restricts what next() delivers to `topics` (all when empty), starting again from the first
  /// message.
  void select(const std::vector<std::string>& topics);

  /// The next message in order; false at the end. At damage, throws BagReadError once (later
  /// calls return false).
  bool next(BagMessage& out);
  /// Fraction of the selected data consumed so far, in [0, 1] (for progress).
  double fraction() const;
  /// Messages in the selection (for progress and reports).
  std::uint64_t selectedMessages() const;

  /// Serialized first message of `topic` (calibration / metadata topics); false when the topic
  /// has no readable message. Does not disturb next(). Throws BagReadError on damage.
  bool firstMessage(const std::string& topic, std::vector<std::uint8_t>& out) const;

 private:
  class Indexed;
  class Recovering;
  std::string path_;
  std::unique_ptr<Indexed> indexed_;
  std::unique_ptr<Recovering> recovering_;
};

}  // namespace rgbdi::bag
