#pragma once
/// \file bag_writer.hpp
/// \brief A bag file writer (format 2.0, chunks uncompressed) that builds each chunk in memory
/// and writes it with its index in one go. rosbag::Bag::write seeks to the end of the file
/// twice for every message (glibc: a flush `write`, `fstat`, `lseek` and a `read` of the last
/// partial block each time), copies the message's connection header, message definition
/// included, to look its connection up, and serializes the message twice (once to the file,
/// once to its chunk buffer): measured, about 7 system calls and 8 us a message on the
/// development VM, which set the pace of a recorded lockstep run (docs/performance.md).
///
/// The file this writes is byte for byte the one rosbag::Bag (uncompressed, the same chunk
/// threshold) writes for the same calls (test/ros/test_bag_writer.cpp), so rosbag, python's
/// rosbag and `rosbag reindex` read it as theirs. What a crash loses is the same too: the
/// open chunk (rosbag's is in the file but has no size yet, and reindexing drops it).

#include <ros/datatypes.h>
#include <ros/message_traits.h>
#include <ros/serialization.h>
#include <ros/time.h>

#include <boost/shared_ptr.hpp>
#include <cstdint>
#include <map>
#include <string>
#include <utility>
#include <vector>

namespace preadaptive_mrac {
namespace ros1 {

/// \brief The connection header a subscriber gets from a publisher of M on `topic` (its
/// fields as roscpp sends them), for writing messages that did not come through a subscriber
/// (test_ros_bag_writer, bench_bag_writer).
template <class M>
boost::shared_ptr<ros::M_string> publisherConnectionHeader(const std::string& topic,
                                                           const std::string& callerid) {
  return boost::shared_ptr<ros::M_string>(
      new ros::M_string{{"callerid", callerid},
                        {"latching", "0"},
                        {"md5sum", ros::message_traits::md5sum<M>()},
                        {"message_definition", ros::message_traits::definition<M>()},
                        {"topic", topic},
                        {"type", ros::message_traits::datatype<M>()},
                        {"tcp_nodelay", "1"}});
}

class BagWriter {
 public:
  BagWriter() = default;
  /// \brief close(), errors logged rather than thrown.
  ~BagWriter();
  BagWriter(const BagWriter&) = delete;
  BagWriter& operator=(const BagWriter&) = delete;

  /// \brief Create (truncate) `path` and write the version line and the file header (no
  /// index yet: a reader sees an unindexed bag until close()). A chunk is written out once it
  /// holds more than `chunk_threshold` bytes [B] (rosbag's default: 768 KB). Throws
  /// std::runtime_error naming the file on failure.
  void open(const std::string& path, std::uint32_t chunk_threshold);
  /// \brief Write the open chunk, the connection and chunk-info records, and the file header
  /// that points to them; close the file. Idempotent. Throws std::runtime_error on failure
  /// (the file is closed either way).
  void close();
  bool isOpen() const { return fd_ >= 0; }
  /// \brief The file being written ("" when none).
  const std::string& fileName() const { return path_; }
  /// \brief Bytes in the file and in the open chunk [B] (rosbag::Bag::getSize's meaning).
  std::uint64_t size() const { return file_size_ + chunk_.size(); }

  /// \brief Append `msg` (any type ros::serialization and ros::message_traits know, e.g. a
  /// generated message or a topic_tools::ShapeShifter) on `topic` at time `t`. A connection
  /// is one (connection header, topic) pair, as in rosbag; without a connection header, one
  /// per topic. Throws std::runtime_error when a full chunk cannot be written.
  template <class M>
  void write(const std::string& topic, const ros::Time& t, const M& msg,
             const boost::shared_ptr<ros::M_string>& connection_header = {}) {
    std::uint32_t id = 0;
    if (!findConnection(topic, connection_header, &id))
      id = addConnection(topic, connection_header, ros::message_traits::datatype(msg),
                         ros::message_traits::md5sum(msg), ros::message_traits::definition(msg));
    const std::uint32_t len = ros::serialization::serializationLength(msg);
    ros::serialization::OStream out(beginRecord(id, t, len), len);
    ros::serialization::serialize(out, msg);
    endRecord();
  }

 private:
  struct Connection {
    std::string topic;
    boost::shared_ptr<ros::M_string> header;  ///< written in its connection records
    bool in_file = false;                     ///< its record is in a chunk already
  };
  struct IndexEntry {
    ros::Time time;
    std::uint32_t offset;  ///< of the message's record in its chunk's data [B]
  };
  struct ChunkInfo {
    std::uint64_t pos = 0;  ///< of the chunk record in the file [B]
    ros::Time start, end;
    std::vector<std::pair<std::uint32_t, std::uint32_t>> counts;  ///< (connection, messages)
  };

  /// \brief The connection of (header, topic) seen before (by the header's address first,
  /// then, for a new address, by its contents).
  bool findConnection(const std::string& topic, const boost::shared_ptr<ros::M_string>& header,
                      std::uint32_t* id);
  std::uint32_t addConnection(const std::string& topic,
                              const boost::shared_ptr<ros::M_string>& header,
                              const std::string& datatype, const std::string& md5sum,
                              const std::string& definition);
  /// \brief Open a chunk if none is, put connection `id`'s record in it the first time, index
  /// the message, append its record header; where its `len` serialized bytes go.
  std::uint8_t* beginRecord(std::uint32_t id, const ros::Time& t, std::uint32_t len);
  /// \brief Write the chunk out once it is over the threshold.
  void endRecord();
  /// \brief The open chunk, its size in its header, and its index records, in one write.
  void writeChunk();
  /// \brief All of `data` at the end of the file (retrying short writes); throws naming the
  /// file.
  void append(const std::vector<std::uint8_t>& data);
  /// \brief Forget the closed file's connections and chunks.
  void reset();
  /// \brief The file header record (index position, connection and chunk counts).
  std::vector<std::uint8_t> fileHeader() const;

  int fd_ = -1;
  std::string path_;
  std::uint32_t chunk_threshold_ = 768 * 1024;
  std::uint64_t file_size_ = 0;          ///< bytes written to the file [B]
  std::uint64_t file_header_pos_ = 0;    ///< after the version line [B]
  std::uint64_t index_pos_ = 0;          ///< of the connection records (0 while writing) [B]
  std::vector<Connection> connections_;  ///< by id
  /// Connection ids by (header address, topic): one lookup a message, no copy. The headers
  /// are held (connections_[].header or keep_), so an address is not reused while here.
  std::map<std::pair<const ros::M_string*, std::string>, std::uint32_t> by_address_;
  std::vector<boost::shared_ptr<ros::M_string>> keep_;
  /// Connection ids by header contents with the topic added (rosbag's key), and by topic for
  /// messages without a connection header.
  std::map<ros::M_string, std::uint32_t> by_contents_;
  std::map<std::string, std::uint32_t> by_topic_;
  bool chunk_open_ = false;
  ChunkInfo chunk_info_;
  std::vector<std::uint8_t> chunk_;                   ///< the open chunk's data
  std::vector<std::vector<IndexEntry>> chunk_index_;  ///< by connection id
  std::vector<ChunkInfo> chunks_;                     ///< written chunks
  std::vector<std::uint8_t> out_;                     ///< a chunk's header and index records
  ros::Time record_time_;                             ///< the message being appended
};

}  // namespace ros1
}  // namespace preadaptive_mrac
