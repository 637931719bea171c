// plucker.Bag: ROS 1 `.bag` and ROS 2 `.db3` bags from Python (bag/bag_reader.h, the reader of
// `plucker bag info` and `--bag`): what the bag holds, and its messages over chosen topics in
// stamp order, decoded into numpy (PointCloud2 as read_pcd's dict, Imu, Image as (H, W) uint8,
// CompressedImage as its bytes).
#include <pybind11/stl.h>

#include "arrays.h"
#include "bindings.h"
#include "plucker/bag/bag_reader.h"

namespace plucker {
namespace python {
namespace {

py::dict InfoDict(const bag::BagInfo& info) {
  py::list topics;
  for (const bag::TopicInfo& t : info.topics) {
    py::dict d;
    d["topic"] = t.topic;
    d["type"] = t.type;
    d["messages"] = t.messages;
    d["first_s"] = t.first_s;
    d["last_s"] = t.last_s;
    topics.append(d);
  }
  py::dict d;
  d["path"] = info.path;
  d["bytes"] = info.bytes;
  d["format"] = info.format;
  d["messages"] = info.messages;
  d["start_s"] = info.start_s;
  d["end_s"] = info.end_s;
  d["topics"] = topics;
  return d;
}

class PyBag {
 public:
  explicit PyBag(const std::string& path) : reader_(std::make_unique<bag::BagReader>(path)) {}

  py::dict Info() const { return InfoDict(reader_->info()); }

  void Select(const std::vector<std::string>& topics, const std::string& stamp) {
    std::vector<bag::TopicRequest> requests;
    for (const std::string& t : topics)
      requests.push_back({t, {bag::kPointCloud2, bag::kImu, bag::kImage, bag::kCompressedImage}});
    reader_->Select(requests, bag::StampSourceFromName(stamp));
    selected_ = true;
  }

  py::dict Next() {
    if (!selected_) throw py::value_error("Bag: select(topics) first");
    bag::MessageRef m;
    if (!reader_->Next(&m)) throw py::stop_iteration();
    py::dict d;
    d["topic"] = m.topic;
    d["type"] = m.type;
    d["index"] = m.index;
    d["stamp_s"] = m.stamp_s;
    d["receive_s"] = m.receive_s;
    d["header_s"] = m.header_s;
    d["stamp_ns"] = m.stamp_ns;
    d["receive_ns"] = m.receive_ns;
    d["header_ns"] = m.header_ns;
    std::string error;
    d["data"] = Decode(m.type, &error);
    d["error"] = error;  // empty, or why data is None (the message is to be skipped)
    return d;
  }

  py::dict Stats() const {
    const bag::StreamStats& s = reader_->stats();
    py::dict d;
    d["messages"] = s.messages;
    d["unreadable"] = s.unreadable;
    d["out_of_order"] = s.out_of_order;
    return d;
  }
  std::vector<std::string> Warnings() const { return reader_->warnings(); }

 private:
  py::object Decode(const std::string& type, std::string* error) const {
    if (type == bag::kPointCloud2) {
      LidarScan scan;
      if (!reader_->ReadScan(&scan, error)) return py::none();
      return ScanDict(std::move(scan));
    }
    if (type == bag::kImu) {
      sensor::ImuSample s;
      if (!reader_->ReadImu(&s, error)) return py::none();
      py::dict d;
      d["t"] = s.t;
      d["gyro"] = ToVector(s.gyro);
      d["accel"] = ToVector(s.accel);
      return d;
    }
    if (type == bag::kImage) {
      bag::GrayImage image;
      if (!reader_->ReadImage(&image, error)) return py::none();
      py::array_t<std::uint8_t> a({image.height, image.width});
      std::copy(image.pixels.begin(), image.pixels.end(), a.mutable_data());
      return a;
    }
    std::string format;
    std::vector<std::uint8_t> bytes;
    if (!reader_->ReadCompressed(&format, &bytes, error)) return py::none();
    py::dict d;
    d["format"] = format;
    d["bytes"] = py::bytes(reinterpret_cast<const char*>(bytes.data()), bytes.size());
    return d;
  }

  std::unique_ptr<bag::BagReader> reader_;
  bool selected_ = false;
};

}  // namespace

void RegisterBag(py::module_& m) {
  // Bag errors (they name the file and the problem) are IoErrors, as the readers' are.
  auto& bag_error = py::register_exception<bag::BagError>(m, "BagError", m.attr("IoError"));
  bag_error.attr("__doc__") =
      "A bag could not be read: an IoError naming the file and the problem.";
  py::class_<PyBag>(m, "Bag",
                    "A ROS 1 .bag, a ROS 2 .db3 or a rosbag2 folder, read without ROS (the reader "
                    "of plucker bag info and --bag; docs/bags.md). Raises IoError naming the file "
                    "and the problem (not a bag, unindexed, truncated, ...).")
      .def(py::init<const std::string&>(), py::arg("path"))
      .def_property_readonly("info", &PyBag::Info,
                             "path, bytes, format, messages, start_s, end_s and per topic its "
                             "type, message count and receive time span (plucker bag info)")
      .def("select", &PyBag::Select, py::arg("topics"), py::arg("stamp") = "header",
           "Streams these topics (PointCloud2, Imu, Image, CompressedImage) in stamp order "
           "(stamp: 'header' or 'receive'); IoError for a topic the bag lacks (naming those it "
           "has) or one of another type. Iterate the bag for the messages.")
      .def("__iter__", [](PyBag& b) -> PyBag& { return b; })
      .def("__next__", &PyBag::Next,
           "The next message: topic, type, index (in its topic), stamp_s (the chosen stamp), "
           "receive_s, header_s and the same in integer ns, data (PointCloud2: read_pcd's dict; "
           "Imu: t, gyro, accel; Image: (H, W) uint8 gray; CompressedImage: format, bytes) and "
           "error (why data is None: a message that does not decode, to be skipped)")
      .def_property_readonly("stats", &PyBag::Stats,
                             "messages delivered, unreadable (skipped), out_of_order")
      .def_property_readonly("warnings", &PyBag::Warnings, "one per unreadable message");
  m.def(
      "bag_info", [](const std::string& path) { return PyBag(path).Info(); }, py::arg("path"),
      "What a bag holds, as plucker bag info lists it (Bag(path).info).");
}

}  // namespace python
}  // namespace plucker
