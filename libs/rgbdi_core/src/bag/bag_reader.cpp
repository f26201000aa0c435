#include "rgbdi/bag/bag_reader.h"

#include <ros/serialization.h>
#include <rosbag/bag.h>
#include <rosbag/exceptions.h>
#include <rosbag/view.h>

#include <algorithm>
#include <filesystem>
#include <iomanip>
#include <map>
#include <set>
#include <sstream>

#include "bag/bag_chunk_scanner.h"
#include "bag/bag_structure_check.h"

namespace rgbdi::bag {
namespace {

// Recovery mode keeps the first message of each topic in memory when it is at most this large:
// calibration and metadata messages, never images.
constexpr std::uint32_t kMaxStashedMessageBytes = 64 * 1024;

std::string seconds(double t) {
  std::ostringstream os;
  os << std::fixed << std::setprecision(6) << t;
  return os.str();
}

bool selected(const std::set<std::string>& wanted, const std::string& topic) {
  return wanted.empty() || wanted.count(topic) > 0;
}

}  // namespace

// ---------------------------------------------------------------------------------------------
// Indexed bags: rosbag::View.
class BagReader::Indexed {
 public:
  Indexed(const std::string& path, const std::vector<std::string>& topics, const BagLimits& limits)
      : path_(path) {
    detail::checkBagStructure(path, limits);  // rosbag allocates what the sizes say
    bag_.open(path, rosbag::bagmode::Read);
    std::map<std::string, BagTopic> by_topic;
    rosbag::View all(bag_);
    for (const rosbag::ConnectionInfo* c : all.getConnections()) {
      BagTopic& t = by_topic[c->topic];
      t.topic = c->topic;
      if (t.datatype.empty()) t.datatype = c->datatype;
      if (t.md5sum.empty()) t.md5sum = c->md5sum;
    }
    for (auto& [name, t] : by_topic) {
      rosbag::View v(bag_, rosbag::TopicQuery(name));
      t.messages = v.size();
      topics_.push_back(t);
    }
    if (all.size() > 0) {
      begin_ = all.getBeginTime().toSec();
      end_ = all.getEndTime().toSec();
    }
    select(topics);
  }

  void select(const std::vector<std::string>& topics) {
    if (topics.empty()) {
      view_ = std::make_unique<rosbag::View>(bag_);
    } else {
      view_ = std::make_unique<rosbag::View>(bag_, rosbag::TopicQuery(topics));
    }
    selected_ = view_->size();
    sel_begin_ = sel_end_ = last_time_ = 0.0;
    if (selected_ > 0) {
      sel_begin_ = view_->getBeginTime().toSec();
      sel_end_ = view_->getEndTime().toSec();
    }
    it_ = view_->begin();
    ordinal_ = 0;
    done_ = false;
  }

  bool next(BagMessage& out) {
    if (done_ || it_ == view_->end()) {
      done_ = true;
      return false;
    }
    const rosbag::MessageInstance m = *it_;
    try {
      const std::uint32_t size = m.size();
      buffer_.resize(size);
      ros::serialization::OStream s(buffer_.data(), size);
      m.write(s);
    } catch (const std::exception& e) {
      done_ = true;
      throw BagReadError(path_ + ": cannot read message " + std::to_string(ordinal_) + " (topic " +
                         m.getTopic() + ", bag time " + seconds(m.getTime().toSec()) +
                         " s): " + e.what() + " - the bag is damaged from here on");
    }
    topic_ = m.getTopic();
    datatype_ = m.getDataType();
    out.topic = &topic_;
    out.datatype = &datatype_;
    out.bag_time = m.getTime().toSec();
    out.data = buffer_.data();
    out.size = static_cast<std::uint32_t>(buffer_.size());
    out.ordinal = ordinal_++;
    out.position = 0;
    last_time_ = out.bag_time;
    ++it_;
    return true;
  }

  bool firstMessage(const std::string& topic, std::vector<std::uint8_t>& out) const {
    rosbag::View v(bag_, rosbag::TopicQuery(topic));
    if (v.size() == 0) return false;
    const rosbag::MessageInstance m = *v.begin();
    try {
      out.resize(m.size());
      ros::serialization::OStream s(out.data(), static_cast<std::uint32_t>(out.size()));
      m.write(s);
    } catch (const std::exception& e) {
      throw BagReadError(path_ + ": cannot read the first message of " + topic + ": " + e.what());
    }
    return true;
  }

  double fraction() const {
    if (done_ || selected_ == 0) return done_ ? 1.0 : 0.0;
    if (sel_end_ <= sel_begin_)
      return static_cast<double>(ordinal_) / static_cast<double>(selected_);
    return std::clamp((last_time_ - sel_begin_) / (sel_end_ - sel_begin_), 0.0, 1.0);
  }

  std::string path_;
  rosbag::Bag bag_;
  std::unique_ptr<rosbag::View> view_;
  rosbag::View::iterator it_;
  std::vector<BagTopic> topics_;
  std::vector<std::uint8_t> buffer_;
  std::string topic_, datatype_;
  double begin_ = 0, end_ = 0, sel_begin_ = 0, sel_end_ = 0, last_time_ = 0;
  std::uint64_t selected_ = 0, ordinal_ = 0;
  bool done_ = false;
};

// ---------------------------------------------------------------------------------------------
// Bags without a readable index: a pre-scan learns topics, counts and small first messages,
// a second scan delivers the messages.
class BagReader::Recovering {
 public:
  Recovering(const std::string& path, const std::vector<std::string>& topics, std::string reason,
             const BagLimits& limits)
      : path_(path), reason_(std::move(reason)), limits_(limits) {
    detail::BagChunkScanner pre(path, limits);
    file_size_ = pre.fileSize();
    std::map<std::uint32_t, std::uint64_t> counts;
    detail::BagChunkScanner::Message m;
    bool any = false;
    try {
      while (pre.next(m)) {
        ++counts[m.connection];
        const std::string& topic = pre.connections().at(m.connection).topic;
        if (m.size <= kMaxStashedMessageBytes && !first_.count(topic))
          first_[topic].assign(m.data, m.data + m.size);
        if (!any) begin_ = m.time;
        begin_ = std::min(begin_, m.time);
        end_ = std::max(end_, m.time);
        any = true;
      }
    } catch (const BagReadError& e) {
      damage_ = e.what();
    }
    readable_bytes_ = std::max<std::uint64_t>(1, pre.position());
    std::map<std::string, BagTopic> by_topic;
    for (const auto& [id, c] : pre.connections()) {
      BagTopic& t = by_topic[c.topic];
      t.topic = c.topic;
      if (t.datatype.empty()) t.datatype = c.datatype;
      if (t.md5sum.empty()) t.md5sum = c.md5sum;
      t.messages += counts[id];
    }
    for (auto& [name, t] : by_topic) topics_.push_back(t);
    select(topics);
  }

  void select(const std::vector<std::string>& topics) {
    wanted_ = std::set<std::string>(topics.begin(), topics.end());
    selected_ = 0;
    for (const BagTopic& t : topics_)
      if (selected(wanted_, t.topic)) selected_ += t.messages;
    scanner_ = std::make_unique<detail::BagChunkScanner>(path_, limits_);
    ordinal_ = 0;
  }

  bool next(BagMessage& out) {
    detail::BagChunkScanner::Message m;
    while (scanner_->next(m)) {
      const detail::ScannedConnection& c = scanner_->connections().at(m.connection);
      if (!selected(wanted_, c.topic)) continue;
      out.topic = &c.topic;
      out.datatype = &c.datatype;
      out.bag_time = m.time;
      out.data = m.data;
      out.size = m.size;
      out.ordinal = ordinal_++;
      out.position = m.position;
      return true;
    }
    return false;
  }

  bool firstMessage(const std::string& topic, std::vector<std::uint8_t>& out) const {
    const auto it = first_.find(topic);
    if (it == first_.end()) return false;
    out = it->second;
    return true;
  }

  double fraction() const {
    return std::clamp(
        static_cast<double>(scanner_->position()) / static_cast<double>(readable_bytes_), 0.0, 1.0);
  }

  std::string path_;
  std::set<std::string> wanted_;
  std::string reason_, damage_;
  BagLimits limits_;
  std::vector<BagTopic> topics_;
  std::map<std::string, std::vector<std::uint8_t>> first_;
  std::unique_ptr<detail::BagChunkScanner> scanner_;
  double begin_ = 0, end_ = 0;
  std::uint64_t file_size_ = 0, readable_bytes_ = 1, selected_ = 0, ordinal_ = 0;
};

// ---------------------------------------------------------------------------------------------

BagReader::BagReader(const std::string& path, const std::vector<std::string>& topics,
                     const BagLimits& limits)
    : path_(path) {
  std::error_code ec;
  if (!std::filesystem::exists(path, ec)) throw BagError(path + ": no such file or directory");
  if (std::filesystem::is_directory(path, ec)) throw BagError(path + ": is a directory, not a bag");
  std::string index_error;
  try {
    indexed_ = std::make_unique<Indexed>(path, topics, limits);
    return;
  } catch (const std::exception& e) {
    index_error = e.what();
  }
  // The index is unreadable: find out whether the chunks are (throws when this is no bag at all).
  std::string reason = "the bag index cannot be read (" + index_error + ")";
  try {
    detail::BagChunkScanner probe(path, limits);
    detail::BagChunkScanner::Message m;
    try {
      probe.next(m);  // reads the file header record, which says where the index should be
    } catch (const BagReadError&) {
      // Damage right at the start: the recovering reader reports it.
    }
    if (probe.indexPosition() > probe.fileSize()) {
      reason += ": the file is truncated (" + std::to_string(probe.fileSize()) +
                " bytes; its index was to start at byte " + std::to_string(probe.indexPosition()) +
                ")";
    } else if (probe.indexPosition() == 0) {
      reason += ": the bag was never indexed (interrupted recording?)";
    }
  } catch (const BagReadError&) {
    throw;
  } catch (const BagError& e) {
    throw BagError(path + ": cannot open as a ROS1 bag: " + index_error + "; " + e.what());
  }
  recovering_ = std::make_unique<Recovering>(path, topics,
                                             reason + "; reading its chunks in file order", limits);
}

BagReader::~BagReader() = default;

bool BagReader::indexed() const { return indexed_ != nullptr; }

const std::string& BagReader::recoveryReason() const {
  static const std::string none;
  return recovering_ ? recovering_->reason_ : none;
}

const std::string& BagReader::damage() const {
  static const std::string none;
  return recovering_ ? recovering_->damage_ : none;
}

const std::vector<BagTopic>& BagReader::topics() const {
  return indexed_ ? indexed_->topics_ : recovering_->topics_;
}

double BagReader::beginTime() const { return indexed_ ? indexed_->begin_ : recovering_->begin_; }
double BagReader::endTime() const { return indexed_ ? indexed_->end_ : recovering_->end_; }

std::uint64_t BagReader::fileSize() const {
  std::error_code ec;
  const auto n = std::filesystem::file_size(path_, ec);
  return ec ? 0 : n;
}

void BagReader::select(const std::vector<std::string>& topics) {
  if (indexed_)
    indexed_->select(topics);
  else
    recovering_->select(topics);
}

bool BagReader::next(BagMessage& out) {
  return indexed_ ? indexed_->next(out) : recovering_->next(out);
}

double BagReader::fraction() const {
  return indexed_ ? indexed_->fraction() : recovering_->fraction();
}

std::uint64_t BagReader::selectedMessages() const {
  return indexed_ ? indexed_->selected_ : recovering_->selected_;
}

bool BagReader::firstMessage(const std::string& topic, std::vector<std::uint8_t>& out) const {
  return indexed_ ? indexed_->firstMessage(topic, out) : recovering_->firstMessage(topic, out);
}

}  // namespace rgbdi::bag
