#include "plucker/bag/db3_internal.h"

#include <sqlite3.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <map>

#include "plucker/bag/bag_reader.h"

namespace plucker {
namespace bag {
namespace {

namespace fs = std::filesystem;

std::string Text(sqlite3_stmt* s, int column) {
  const unsigned char* t = sqlite3_column_text(s, column);
  return t ? reinterpret_cast<const char*>(t) : "";
}

// A prepared statement that finalises itself.
struct Statement {
  Statement(sqlite3* db, const std::string& path, const char* sql) {
    if (sqlite3_prepare_v2(db, sql, -1, &s, nullptr) != SQLITE_OK)
      throw BagError(path + ": " + sqlite3_errmsg(db));
  }
  ~Statement() { sqlite3_finalize(s); }
  sqlite3_stmt* s = nullptr;
};

void Exec(sqlite3* db, const std::string& path, const char* sql) {
  char* error = nullptr;
  if (sqlite3_exec(db, sql, nullptr, nullptr, &error) != SQLITE_OK) {
    const std::string e = error ? error : sqlite3_errmsg(db);
    sqlite3_free(error);
    throw BagError(path + ": " + e);
  }
}

}  // namespace

std::string ResolveDb3(const std::string& path) {
  std::error_code ec;
  if (!fs::is_directory(path, ec)) return path;
  const fs::path meta = fs::path(path) / "metadata.yaml";
  if (!fs::exists(meta, ec))
    throw BagError(path + ": a folder, but not a rosbag2 folder (no metadata.yaml)");
  std::ifstream in(meta);
  for (std::string line; std::getline(in, line);) {
    const std::size_t at = line.find("compression_format:");
    if (at == std::string::npos) continue;
    std::string v = line.substr(at + 19);
    v.erase(std::remove_if(v.begin(), v.end(),
                           [](char c) { return c == ' ' || c == '"' || c == '\'' || c == '\r'; }),
            v.end());
    if (!v.empty())
      throw BagError(meta.string() + ": compressed rosbag2 (" + v +
                     ") is not read; `ros2 bag decompress` or `ros2 bag convert` writes it "
                     "uncompressed");
  }
  std::vector<std::string> db3, mcap;
  for (const fs::directory_entry& e : fs::directory_iterator(path, ec)) {
    if (e.path().extension() == ".db3") db3.push_back(e.path().string());
    if (e.path().extension() == ".mcap") mcap.push_back(e.path().string());
  }
  if (db3.empty() && !mcap.empty())
    throw BagError(path + ": MCAP storage (" + fs::path(mcap[0]).filename().string() +
                   ") is not read, only .db3; see docs/bags.md (ros2 bag convert)");
  if (db3.empty()) throw BagError(path + ": rosbag2 folder without a .db3 file");
  if (db3.size() > 1)
    throw BagError(path + ": split rosbag2 (" + std::to_string(db3.size()) +
                   " .db3 files) is not read; give one of its .db3 files");
  return db3[0];
}

Db3File::Db3File(const std::string& path) : path_(path) {
  if (sqlite3_open_v2(path.c_str(), &db_, SQLITE_OPEN_READONLY, nullptr) != SQLITE_OK) {
    const std::string e = db_ ? sqlite3_errmsg(db_) : "out of memory";
    sqlite3_close(db_);
    throw BagError(path + ": cannot open as SQLite: " + e);
  }
  try {
    {
      Statement tables(db_, path_ + ": not an SQLite database",
                       "SELECT name FROM sqlite_master "
                       "WHERE type = 'table'");
      bool topics = false, messages = false;
      while (sqlite3_step(tables.s) == SQLITE_ROW) {
        topics = topics || Text(tables.s, 0) == "topics";
        messages = messages || Text(tables.s, 0) == "messages";
      }
      if (!topics || !messages)
        throw BagError(path + ": an SQLite database but not a rosbag2 .db3 (no " +
                       (topics ? "messages" : "topics") + " table)");
    }
    std::map<std::int64_t, Db3Topic> by_id;
    Statement t(db_, path_, "SELECT id, name, type, serialization_format FROM topics");
    while (sqlite3_step(t.s) == SQLITE_ROW) {
      Db3Topic& topic = by_id[sqlite3_column_int64(t.s, 0)];
      topic.id = sqlite3_column_int64(t.s, 0);
      topic.name = Text(t.s, 1), topic.type = Text(t.s, 2), topic.format = Text(t.s, 3);
    }
    Statement c(db_, path_,
                "SELECT topic_id, COUNT(*), MIN(timestamp), MAX(timestamp) FROM messages "
                "GROUP BY topic_id");
    int rc = 0;
    while ((rc = sqlite3_step(c.s)) == SQLITE_ROW) {
      const auto it = by_id.find(sqlite3_column_int64(c.s, 0));
      if (it == by_id.end()) continue;  // messages of no topic: not listed, never read
      it->second.messages = static_cast<std::size_t>(sqlite3_column_int64(c.s, 1));
      it->second.first_ns = sqlite3_column_int64(c.s, 2);
      it->second.last_ns = sqlite3_column_int64(c.s, 3);
    }
    if (rc != SQLITE_DONE) throw BagError(path + ": " + sqlite3_errmsg(db_));
    for (const auto& [id, topic] : by_id) topics_.push_back(topic);
    std::sort(topics_.begin(), topics_.end(),
              [](const Db3Topic& a, const Db3Topic& b) { return a.name < b.name; });
  } catch (...) {
    sqlite3_close(db_);
    throw;
  }
}

Db3File::~Db3File() { sqlite3_close(db_); }

std::unique_ptr<Db3Cursor> Db3File::Open(std::int64_t topic_id) const {
  return std::make_unique<Db3Cursor>(db_, path_, topic_id);
}

Db3Cursor::Db3Cursor(sqlite3* db, const std::string& path, std::int64_t topic_id) : path_(path) {
  // By id (insertion = receive order): streams without sorting the table.
  if (sqlite3_prepare_v2(db, "SELECT timestamp, data FROM messages WHERE topic_id = ? ORDER BY id",
                         -1, &statement_, nullptr) != SQLITE_OK)
    throw BagError(path + ": " + sqlite3_errmsg(db));
  sqlite3_bind_int64(statement_, 1, topic_id);
}

Db3Cursor::~Db3Cursor() { sqlite3_finalize(statement_); }

bool Db3Cursor::Next(std::int64_t* receive_ns, const std::uint8_t** data, std::size_t* size) {
  const int rc = sqlite3_step(statement_);
  if (rc == SQLITE_DONE) return false;
  if (rc != SQLITE_ROW)
    throw BagError(path_ + ": reading messages: " + sqlite3_errmsg(sqlite3_db_handle(statement_)));
  *receive_ns = sqlite3_column_int64(statement_, 0);
  *data = static_cast<const std::uint8_t*>(sqlite3_column_blob(statement_, 1));
  *size = static_cast<std::size_t>(sqlite3_column_bytes(statement_, 1));
  return true;
}

struct Db3Writer::Impl {
  std::string path;
  sqlite3* db = nullptr;
  sqlite3_stmt* insert = nullptr;
  std::map<std::string, std::int64_t> topic_ids;
  bool open = false;
};

Db3Writer::Db3Writer(const std::string& path) : impl_(new Impl) {
  Impl& d = *impl_;
  d.path = path;
  std::error_code ec;
  if (fs::exists(path, ec)) throw BagError(path + ": exists; refusing to overwrite it");
  if (sqlite3_open_v2(path.c_str(), &d.db, SQLITE_OPEN_READWRITE | SQLITE_OPEN_CREATE, nullptr) !=
      SQLITE_OK) {
    const std::string e = d.db ? sqlite3_errmsg(d.db) : "out of memory";
    sqlite3_close(d.db);
    throw BagError(path + ": cannot create: " + e);
  }
  try {
    // rosbag2's schema (Humble: offered_qos_profiles; the schema table as rosbag2 writes it).
    Exec(d.db, path,
         "PRAGMA journal_mode = MEMORY; PRAGMA synchronous = OFF;"
         "CREATE TABLE schema(schema_version INTEGER PRIMARY KEY, ros_distro TEXT NOT NULL);"
         "INSERT INTO schema VALUES (3, 'humble');"
         "CREATE TABLE topics(id INTEGER PRIMARY KEY, name TEXT NOT NULL, type TEXT NOT NULL,"
         " serialization_format TEXT NOT NULL, offered_qos_profiles TEXT NOT NULL);"
         "CREATE TABLE messages(id INTEGER PRIMARY KEY, topic_id INTEGER NOT NULL,"
         " timestamp INTEGER NOT NULL, data BLOB NOT NULL);"
         "CREATE INDEX timestamp_idx ON messages (timestamp ASC);"
         "BEGIN TRANSACTION;");
    if (sqlite3_prepare_v2(d.db, "INSERT INTO messages (topic_id, timestamp, data) VALUES (?,?,?)",
                           -1, &d.insert, nullptr) != SQLITE_OK)
      throw BagError(path + ": " + sqlite3_errmsg(d.db));
  } catch (...) {
    sqlite3_close(d.db);
    throw;
  }
  d.open = true;
}

Db3Writer::~Db3Writer() {
  try {
    Close();
  } catch (...) {  // a destructor does not throw; Close() reports it to callers that ask
  }
  sqlite3_finalize(impl_->insert);
  sqlite3_close(impl_->db);
}

void Db3Writer::Write(const std::string& topic, const std::string& type, std::int64_t receive_ns,
                      const std::vector<std::uint8_t>& data) {
  Impl& d = *impl_;
  if (!d.open) throw BagError(d.path + ": written after Close");
  auto it = d.topic_ids.find(topic);
  if (it == d.topic_ids.end()) {
    Statement s(d.db, d.path,
                "INSERT INTO topics (name, type, serialization_format, offered_qos_profiles) "
                "VALUES (?, ?, 'cdr', '')");
    sqlite3_bind_text(s.s, 1, topic.c_str(), -1, SQLITE_TRANSIENT);
    sqlite3_bind_text(s.s, 2, type.c_str(), -1, SQLITE_TRANSIENT);
    if (sqlite3_step(s.s) != SQLITE_DONE) throw BagError(d.path + ": " + sqlite3_errmsg(d.db));
    it = d.topic_ids.emplace(topic, sqlite3_last_insert_rowid(d.db)).first;
  }
  sqlite3_reset(d.insert);
  sqlite3_bind_int64(d.insert, 1, it->second);
  sqlite3_bind_int64(d.insert, 2, receive_ns);
  sqlite3_bind_blob(d.insert, 3, data.data(), static_cast<int>(data.size()), SQLITE_STATIC);
  if (sqlite3_step(d.insert) != SQLITE_DONE)
    throw BagError(d.path + ": write failed: " + sqlite3_errmsg(d.db));
}

void Db3Writer::Close() {
  Impl& d = *impl_;
  if (!d.open) return;
  d.open = false;
  Exec(d.db, d.path, "COMMIT;");
}

}  // namespace bag
}  // namespace plucker
