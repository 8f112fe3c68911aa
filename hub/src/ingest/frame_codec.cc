// CameraFrame <-> v1::MarkerFrame; centroids quantised to the wire's 1/256 px.
#include "ingest/frame_codec.h"

#include "wire/chunking.h"
#include "wire/packet.h"

namespace mocap {

v1::MarkerFrame ToMarkerFrame(const CameraFrame& frame) {
  v1::MarkerFrame m;
  m.set_node_id(frame.camera_id);
  m.set_frame_number(frame.frame_number);
  m.set_trigger_time_ns(frame.trigger_time_ns);
  m.set_capture_time_ns(frame.capture_time_ns);
  m.set_send_time_ns(frame.send_time_ns);
  m.set_width(frame.width);
  m.set_height(frame.height);
  m.set_flags(frame.flags);
  for (const Blob& b : frame.blobs) {
    v1::Marker* marker = m.add_markers();
    marker->set_x_q8(wire::ToSubpixel(b.pixel.x()));
    marker->set_y_q8(wire::ToSubpixel(b.pixel.y()));
    marker->set_area(b.area);
    marker->set_peak(b.peak);
    marker->set_mean(b.mean);
    marker->set_flags(b.flags);
  }
  return m;
}

CameraFrame FromMarkerFrame(const v1::MarkerFrame& m, uint64_t receive_time_ns) {
  CameraFrame frame;
  frame.camera_id = m.node_id();
  frame.frame_number = m.frame_number();
  frame.trigger_time_ns = m.trigger_time_ns();
  frame.capture_time_ns = m.capture_time_ns();
  frame.send_time_ns = m.send_time_ns();
  frame.receive_time_ns = receive_time_ns;
  frame.width = m.width();
  frame.height = m.height();
  frame.flags = m.flags();
  frame.blobs.reserve(m.markers_size());
  for (const v1::Marker& marker : m.markers()) {
    Blob b;
    b.pixel = Eigen::Vector2d(wire::FromSubpixel(marker.x_q8()), wire::FromSubpixel(marker.y_q8()));
    b.area = marker.area();
    b.peak = marker.peak();
    b.mean = marker.mean();
    b.flags = marker.flags();
    frame.blobs.push_back(b);
  }
  return frame;
}

std::vector<std::vector<uint8_t>> EncodeCameraFrame(const CameraFrame& frame) {
  std::vector<std::vector<uint8_t>> datagrams;
  for (const v1::Packet& packet : wire::SplitMarkerFrame(ToMarkerFrame(frame)))
    datagrams.push_back(wire::Encode(packet));
  return datagrams;
}

}  // namespace mocap
