#include "plucker/bag/ros2_messages_internal.h"

#include "plucker/bag/cdr.h"

namespace plucker {
namespace bag {
namespace ros2 {
namespace {

// std_msgs/msg/Header: builtin_interfaces/msg/Time (int32 sec, uint32 nanosec), string frame_id.
void ReadHeader(CdrReader* r, std_msgs::Header* h) {
  const std::int32_t sec = r->Get<std::int32_t>("header.stamp.sec");
  const std::uint32_t nsec = r->Get<std::uint32_t>("header.stamp.nanosec");
  if (sec < 0) throw CdrError("negative header stamp (" + std::to_string(sec) + " s)");
  if (nsec >= 1000000000u)
    throw CdrError("header.stamp.nanosec " + std::to_string(nsec) + " is not below 1e9");
  h->seq = 0;
  h->stamp.sec = static_cast<std::uint32_t>(sec);
  h->stamp.nsec = nsec;
  h->frame_id = r->String("header.frame_id");
}

void WriteHeader(const std_msgs::Header& h, CdrWriter* w) {
  w->Put<std::int32_t>(static_cast<std::int32_t>(h.stamp.sec));
  w->Put<std::uint32_t>(h.stamp.nsec);
  w->String(h.frame_id);
}

template <typename V>
void ReadVector3(CdrReader* r, V* v, const char* what) {
  v->x = r->Get<double>(what), v->y = r->Get<double>(what), v->z = r->Get<double>(what);
}

template <typename A>
void ReadArray(CdrReader* r, A* a, const char* what) {
  for (double& x : *a) x = r->Get<double>(what);
}

void ReadData(CdrReader* r, std::vector<std::uint8_t>* data, const char* what) {
  r->Bytes(r->Count(1, what), data, what);
}

}  // namespace

std::string Ros1Type(const std::string& t) {
  const std::size_t at = t.find("/msg/");
  return at == std::string::npos ? t : t.substr(0, at) + "/" + t.substr(at + 5);
}

std::string Ros2Type(const std::string& t) {
  const std::size_t at = t.find('/');
  if (at == std::string::npos || t.find("/msg/") != std::string::npos) return t;
  return t.substr(0, at) + "/msg" + t.substr(at);
}

void Decode(const std::uint8_t* data, std::size_t size, sensor_msgs::Imu* m) {
  CdrReader r(data, size);
  ReadHeader(&r, &m->header);
  m->orientation.x = r.Get<double>("orientation"), m->orientation.y = r.Get<double>("orientation");
  m->orientation.z = r.Get<double>("orientation"), m->orientation.w = r.Get<double>("orientation");
  ReadArray(&r, &m->orientation_covariance, "orientation_covariance");
  ReadVector3(&r, &m->angular_velocity, "angular_velocity");
  ReadArray(&r, &m->angular_velocity_covariance, "angular_velocity_covariance");
  ReadVector3(&r, &m->linear_acceleration, "linear_acceleration");
  ReadArray(&r, &m->linear_acceleration_covariance, "linear_acceleration_covariance");
}

void Decode(const std::uint8_t* data, std::size_t size, sensor_msgs::Image* m) {
  CdrReader r(data, size);
  ReadHeader(&r, &m->header);
  m->height = r.Get<std::uint32_t>("height");
  m->width = r.Get<std::uint32_t>("width");
  m->encoding = r.String("encoding");
  m->is_bigendian = r.Get<std::uint8_t>("is_bigendian");
  m->step = r.Get<std::uint32_t>("step");
  ReadData(&r, &m->data, "data");
}

void Decode(const std::uint8_t* data, std::size_t size, sensor_msgs::CompressedImage* m) {
  CdrReader r(data, size);
  ReadHeader(&r, &m->header);
  m->format = r.String("format");
  ReadData(&r, &m->data, "data");
}

void Decode(const std::uint8_t* data, std::size_t size, sensor_msgs::PointCloud2* m) {
  CdrReader r(data, size);
  ReadHeader(&r, &m->header);
  m->height = r.Get<std::uint32_t>("height");
  m->width = r.Get<std::uint32_t>("width");
  // A PointField takes at least 13 bytes: string length, offset, datatype, count.
  m->fields.resize(r.Count(13, "fields"));
  for (sensor_msgs::PointField& f : m->fields) {
    f.name = r.String("fields.name");
    f.offset = r.Get<std::uint32_t>("fields.offset");
    f.datatype = r.Get<std::uint8_t>("fields.datatype");
    f.count = r.Get<std::uint32_t>("fields.count");
  }
  m->is_bigendian = r.Get<std::uint8_t>("is_bigendian");
  m->point_step = r.Get<std::uint32_t>("point_step");
  m->row_step = r.Get<std::uint32_t>("row_step");
  ReadData(&r, &m->data, "data");
  m->is_dense = r.Get<std::uint8_t>("is_dense");
}

std::vector<std::uint8_t> Encode(const sensor_msgs::Imu& m) {
  CdrWriter w;
  WriteHeader(m.header, &w);
  for (double x : {m.orientation.x, m.orientation.y, m.orientation.z, m.orientation.w})
    w.Put<double>(x);
  for (double x : m.orientation_covariance) w.Put<double>(x);
  for (double x : {m.angular_velocity.x, m.angular_velocity.y, m.angular_velocity.z})
    w.Put<double>(x);
  for (double x : m.angular_velocity_covariance) w.Put<double>(x);
  for (double x : {m.linear_acceleration.x, m.linear_acceleration.y, m.linear_acceleration.z})
    w.Put<double>(x);
  for (double x : m.linear_acceleration_covariance) w.Put<double>(x);
  return w.buffer();
}

std::vector<std::uint8_t> Encode(const sensor_msgs::Image& m) {
  CdrWriter w;
  WriteHeader(m.header, &w);
  w.Put<std::uint32_t>(m.height);
  w.Put<std::uint32_t>(m.width);
  w.String(m.encoding);
  w.Put<std::uint8_t>(m.is_bigendian);
  w.Put<std::uint32_t>(m.step);
  w.Bytes(m.data);
  return w.buffer();
}

std::vector<std::uint8_t> Encode(const sensor_msgs::CompressedImage& m) {
  CdrWriter w;
  WriteHeader(m.header, &w);
  w.String(m.format);
  w.Bytes(m.data);
  return w.buffer();
}

std::vector<std::uint8_t> Encode(const sensor_msgs::PointCloud2& m) {
  CdrWriter w;
  WriteHeader(m.header, &w);
  w.Put<std::uint32_t>(m.height);
  w.Put<std::uint32_t>(m.width);
  w.Put<std::uint32_t>(static_cast<std::uint32_t>(m.fields.size()));
  for (const sensor_msgs::PointField& f : m.fields) {
    w.String(f.name);
    w.Put<std::uint32_t>(f.offset);
    w.Put<std::uint8_t>(f.datatype);
    w.Put<std::uint32_t>(f.count);
  }
  w.Put<std::uint8_t>(m.is_bigendian);
  w.Put<std::uint32_t>(m.point_step);
  w.Put<std::uint32_t>(m.row_step);
  w.Bytes(m.data);
  w.Put<std::uint8_t>(m.is_dense);
  return w.buffer();
}

}  // namespace ros2
}  // namespace bag
}  // namespace plucker
