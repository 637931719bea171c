// rosbag2's SQLite3 storage (`.db3`): the `topics` table (id, name, type, serialization_format)
// and the `messages` table (topic_id, timestamp = receive time in ns, data = the serialised
// message). Read-only access with per-topic cursors that stream one row at a time, and a writer
// for tests and conversions. Private to the bag layer; errors are BagError naming the file.
#pragma once

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

struct sqlite3;
struct sqlite3_stmt;

namespace plucker {
namespace bag {

struct Db3Topic {
  std::int64_t id = 0;
  std::string name, type, format;  // type as recorded ("sensor_msgs/msg/Imu"), format "cdr"
  std::size_t messages = 0;
  std::int64_t first_ns = 0, last_ns = 0;  // receive times
};

// The .db3 a path names: the file itself, or the one .db3 of a rosbag2 folder (metadata.yaml).
// Throws BagError for a folder without metadata.yaml or with no / several .db3 files, MCAP
// storage, or compressed messages.
std::string ResolveDb3(const std::string& path);

class Db3Cursor {
 public:
  Db3Cursor(sqlite3* db, const std::string& path, std::int64_t topic_id);
  ~Db3Cursor();
  Db3Cursor(const Db3Cursor&) = delete;
  Db3Cursor& operator=(const Db3Cursor&) = delete;
  // The topic's next message in insertion (receive) order; false at the end. The data pointer
  // stays valid until the next call. Throws BagError when SQLite fails.
  bool Next(std::int64_t* receive_ns, const std::uint8_t** data, std::size_t* size);

 private:
  sqlite3_stmt* statement_ = nullptr;
  std::string path_;
};

class Db3File {
 public:
  explicit Db3File(const std::string& db3_path);  // BagError: not SQLite, not a rosbag2 db
  ~Db3File();
  Db3File(const Db3File&) = delete;
  Db3File& operator=(const Db3File&) = delete;
  const std::vector<Db3Topic>& topics() const { return topics_; }  // sorted by name
  std::unique_ptr<Db3Cursor> Open(std::int64_t topic_id) const;

 private:
  sqlite3* db_ = nullptr;
  std::string path_;
  std::vector<Db3Topic> topics_;
};

class Db3Writer {
 public:
  explicit Db3Writer(const std::string& path);  // BagError when it exists or cannot be made
  ~Db3Writer();
  Db3Writer(const Db3Writer&) = delete;
  Db3Writer& operator=(const Db3Writer&) = delete;
  // type: the ROS 2 name ("sensor_msgs/msg/Imu"); data: the CDR payload.
  void Write(const std::string& topic, const std::string& type, std::int64_t receive_ns,
             const std::vector<std::uint8_t>& data);
  void Close();  // commits; idempotent

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace bag
}  // namespace plucker
