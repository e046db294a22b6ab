#include "preadaptive_mrac/ros/bag_writer.hpp"

#include <fcntl.h>
#include <ros/console.h>
#include <rosbag/constants.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <stdexcept>

namespace preadaptive_mrac {
namespace ros1 {
namespace {

template <class T>
void put(std::vector<std::uint8_t>& buf, const T& v) {
  const auto* p = reinterpret_cast<const std::uint8_t*>(&v);
  buf.insert(buf.end(), p, p + sizeof(T));
}

/// A header field's value as rosbag stores a number: its bytes (little endian).
template <class T>
std::string bytes(const T& v) {
  return std::string(reinterpret_cast<const char*>(&v), sizeof(T));
}

/// A time as rosbag stores it: sec, then nsec.
std::string bytes(const ros::Time& t) { return bytes(t.sec) + bytes(t.nsec); }

/// A record header: its length, then each field as length, `name=value` (the map's order, as
/// ros::Header::write and so rosbag write it).
void putHeader(std::vector<std::uint8_t>& buf, const ros::M_string& fields) {
  std::uint32_t len = 0;
  for (const auto& f : fields)
    len += 4 + static_cast<std::uint32_t>(f.first.size() + 1 + f.second.size());
  put(buf, len);
  for (const auto& f : fields) {
    put(buf, static_cast<std::uint32_t>(f.first.size() + 1 + f.second.size()));
    buf.insert(buf.end(), f.first.begin(), f.first.end());
    buf.push_back('=');
    buf.insert(buf.end(), f.second.begin(), f.second.end());
  }
}

/// A connection record: its id and topic, then the connection header.
void putConnection(std::vector<std::uint8_t>& buf, std::uint32_t id, const std::string& topic,
                   const ros::M_string& header) {
  putHeader(buf, {{rosbag::OP_FIELD_NAME, bytes(rosbag::OP_CONNECTION)},
                  {rosbag::TOPIC_FIELD_NAME, topic},
                  {rosbag::CONNECTION_FIELD_NAME, bytes(id)}});
  putHeader(buf, header);
}

std::runtime_error ioError(const std::string& what, const std::string& path) {
  return std::runtime_error(what + " " + path + ": " + std::strerror(errno));
}

}  // namespace

BagWriter::~BagWriter() {
  try {
    close();
  } catch (const std::exception& e) {
    ROS_ERROR("%s", e.what());
  }
}

void BagWriter::open(const std::string& path, std::uint32_t chunk_threshold) {
  if (isOpen()) throw std::runtime_error("bag " + path_ + " is open already");
  fd_ = ::open(path.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0666);
  if (fd_ < 0) throw ioError("cannot create", path);
  path_ = path;
  chunk_threshold_ = chunk_threshold;
  file_size_ = 0;
  index_pos_ = 0;
  const std::string version = "#ROSBAG V" + rosbag::VERSION + "\n";
  file_header_pos_ = version.size();
  std::vector<std::uint8_t> start(version.begin(), version.end());
  const std::vector<std::uint8_t> header = fileHeader();
  start.insert(start.end(), header.begin(), header.end());
  append(start);
}

std::vector<std::uint8_t> BagWriter::fileHeader() const {
  std::vector<std::uint8_t> buf;
  putHeader(buf,
            {{rosbag::OP_FIELD_NAME, bytes(rosbag::OP_FILE_HEADER)},
             {rosbag::INDEX_POS_FIELD_NAME, bytes(index_pos_)},
             {rosbag::CONNECTION_COUNT_FIELD_NAME,
              bytes(static_cast<std::uint32_t>(connections_.size()))},
             {rosbag::CHUNK_COUNT_FIELD_NAME, bytes(static_cast<std::uint32_t>(chunks_.size()))}});
  // Padded with spaces to FILE_HEADER_LENGTH, so that rewriting it at close fits in place.
  const std::uint32_t header_len = static_cast<std::uint32_t>(buf.size()) - 4;
  const std::uint32_t pad =
      header_len < rosbag::FILE_HEADER_LENGTH ? rosbag::FILE_HEADER_LENGTH - header_len : 0;
  put(buf, pad);
  buf.insert(buf.end(), pad, ' ');
  return buf;
}

bool BagWriter::findConnection(const std::string& topic,
                               const boost::shared_ptr<ros::M_string>& header, std::uint32_t* id) {
  if (!header) {
    const auto it = by_topic_.find(topic);
    if (it == by_topic_.end()) return false;
    *id = it->second;
    return true;
  }
  const auto key = std::make_pair(static_cast<const ros::M_string*>(header.get()), topic);
  const auto it = by_address_.find(key);
  if (it != by_address_.end()) {
    *id = it->second;
    return true;
  }
  // A header at a new address: rosbag's key, its contents with the topic.
  ros::M_string contents(*header);
  contents["topic"] = topic;
  const auto c = by_contents_.find(contents);
  if (c == by_contents_.end()) return false;
  keep_.push_back(header);
  by_address_.emplace(key, c->second);
  *id = c->second;
  return true;
}

std::uint32_t BagWriter::addConnection(const std::string& topic,
                                       const boost::shared_ptr<ros::M_string>& header,
                                       const std::string& datatype, const std::string& md5sum,
                                       const std::string& definition) {
  const auto id = static_cast<std::uint32_t>(connections_.size());
  Connection c;
  c.topic = topic;
  if (header) {
    c.header = header;
    ros::M_string contents(*header);
    contents["topic"] = topic;
    by_contents_.emplace(std::move(contents), id);
    by_address_.emplace(std::make_pair(static_cast<const ros::M_string*>(header.get()), topic), id);
  } else {
    c.header = boost::shared_ptr<ros::M_string>(new ros::M_string{
        {"type", datatype}, {"md5sum", md5sum}, {"message_definition", definition}});
    by_topic_.emplace(topic, id);
  }
  connections_.push_back(std::move(c));
  chunk_index_.emplace_back();
  return id;
}

std::uint8_t* BagWriter::beginRecord(std::uint32_t id, const ros::Time& t, std::uint32_t len) {
  if (!isOpen()) throw std::runtime_error("bag not open");
  if (!chunk_open_) {
    chunk_info_ = ChunkInfo();
    chunk_info_.pos = file_size_;
    chunk_info_.start = chunk_info_.end = t;
    chunk_.clear();
    chunk_open_ = true;
  }
  Connection& c = connections_[id];
  if (!c.in_file) {
    // Its first message: the connection record goes in the chunk before it (as rosbag does).
    putConnection(chunk_, id, c.topic, *c.header);
    c.in_file = true;
  }
  chunk_index_[id].push_back({t, static_cast<std::uint32_t>(chunk_.size())});
  // The message data record: header (conn, op, time: the map's order), data length, data.
  put(chunk_, std::uint32_t{4 + 5 + 4 + 4 + 3 + 1 + 4 + 5 + 8});
  put(chunk_, std::uint32_t{5 + 4});
  chunk_.insert(chunk_.end(), {'c', 'o', 'n', 'n', '='});
  put(chunk_, id);
  put(chunk_, std::uint32_t{3 + 1});
  chunk_.insert(chunk_.end(), {'o', 'p', '='});
  put(chunk_, rosbag::OP_MSG_DATA);
  put(chunk_, std::uint32_t{5 + 8});
  chunk_.insert(chunk_.end(), {'t', 'i', 'm', 'e', '='});
  put(chunk_, t.sec);
  put(chunk_, t.nsec);
  put(chunk_, len);
  record_time_ = t;
  const std::size_t at = chunk_.size();
  chunk_.resize(at + len);
  return chunk_.data() + at;
}

void BagWriter::endRecord() {
  if (record_time_ > chunk_info_.end)
    chunk_info_.end = record_time_;
  else if (record_time_ < chunk_info_.start)
    chunk_info_.start = record_time_;
  if (chunk_.size() > chunk_threshold_) writeChunk();
}

void BagWriter::writeChunk() {
  out_.clear();
  const auto size = static_cast<std::uint32_t>(chunk_.size());
  putHeader(out_, {{rosbag::OP_FIELD_NAME, bytes(rosbag::OP_CHUNK)},
                   {rosbag::COMPRESSION_FIELD_NAME, rosbag::COMPRESSION_NONE},
                   {rosbag::SIZE_FIELD_NAME, bytes(size)}});
  put(out_, size);
  append(out_);
  append(chunk_);
  // The index records after it, one per connection in it (by id), entries by time (ties in
  // the order written: rosbag's multiset).
  out_.clear();
  for (std::uint32_t id = 0; id < chunk_index_.size(); ++id) {
    std::vector<IndexEntry>& index = chunk_index_[id];
    if (index.empty()) continue;
    std::stable_sort(index.begin(), index.end(),
                     [](const IndexEntry& a, const IndexEntry& b) { return a.time < b.time; });
    const auto count = static_cast<std::uint32_t>(index.size());
    putHeader(out_, {{rosbag::OP_FIELD_NAME, bytes(rosbag::OP_INDEX_DATA)},
                     {rosbag::CONNECTION_FIELD_NAME, bytes(id)},
                     {rosbag::VER_FIELD_NAME, bytes(rosbag::INDEX_VERSION)},
                     {rosbag::COUNT_FIELD_NAME, bytes(count)}});
    put(out_, std::uint32_t{count * 12});
    for (const IndexEntry& e : index) {
      put(out_, e.time.sec);
      put(out_, e.time.nsec);
      put(out_, e.offset);
    }
    chunk_info_.counts.emplace_back(id, count);
    index.clear();
  }
  append(out_);
  chunks_.push_back(chunk_info_);
  chunk_.clear();
  chunk_open_ = false;
}

void BagWriter::append(const std::vector<std::uint8_t>& data) {
  std::size_t done = 0;
  while (done < data.size()) {
    const ssize_t n = ::write(fd_, data.data() + done, data.size() - done);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) throw ioError("cannot write", path_);
    done += static_cast<std::size_t>(n);
  }
  file_size_ += data.size();
}

void BagWriter::close() {
  if (!isOpen()) return;
  try {
    if (chunk_open_) writeChunk();
    index_pos_ = file_size_;
    out_.clear();
    for (std::uint32_t id = 0; id < connections_.size(); ++id)
      putConnection(out_, id, connections_[id].topic, *connections_[id].header);
    for (const ChunkInfo& ci : chunks_) {
      putHeader(out_,
                {{rosbag::OP_FIELD_NAME, bytes(rosbag::OP_CHUNK_INFO)},
                 {rosbag::VER_FIELD_NAME, bytes(rosbag::CHUNK_INFO_VERSION)},
                 {rosbag::CHUNK_POS_FIELD_NAME, bytes(ci.pos)},
                 {rosbag::START_TIME_FIELD_NAME, bytes(ci.start)},
                 {rosbag::END_TIME_FIELD_NAME, bytes(ci.end)},
                 {rosbag::COUNT_FIELD_NAME, bytes(static_cast<std::uint32_t>(ci.counts.size()))}});
      put(out_, static_cast<std::uint32_t>(8 * ci.counts.size()));
      for (const auto& c : ci.counts) {
        put(out_, c.first);
        put(out_, c.second);
      }
    }
    append(out_);
    // The file header, now with the index's position, over the one written at open.
    const std::vector<std::uint8_t> header = fileHeader();
    if (::pwrite(fd_, header.data(), header.size(), static_cast<off_t>(file_header_pos_)) !=
        static_cast<ssize_t>(header.size()))
      throw ioError("cannot write the header of", path_);
  } catch (...) {
    ::close(fd_);
    reset();
    throw;
  }
  if (::close(fd_) != 0) {
    const std::runtime_error e = ioError("cannot close", path_);
    reset();
    throw e;
  }
  reset();
}

void BagWriter::reset() {
  // Ready for another open(): nothing of the closed file carried over (but its name).
  fd_ = -1;
  connections_.clear();
  by_address_.clear();
  keep_.clear();
  by_contents_.clear();
  by_topic_.clear();
  chunk_index_.clear();
  chunks_.clear();
  chunk_open_ = false;
}

}  // namespace ros1
}  // namespace preadaptive_mrac
