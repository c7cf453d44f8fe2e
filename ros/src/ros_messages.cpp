#include "ros_messages.h"

#include <algorithm>
#include <cmath>
#include <cstring>

#include <fmt/format.h>
#include <opencv2/imgproc.hpp>
#include <sensor_msgs/image_encodings.h>
#include "sgslam/semantic/object_json.h"

namespace sgslam::ros_bridge {

namespace {

// The message's pixels as a Mat over its buffer (no copy), or an error naming what
// does not fit.
Converted Wrap(const sensor_msgs::Image& msg, int type, const char* what) {
  Converted c;
  const std::size_t row = static_cast<std::size_t>(msg.width) * CV_ELEM_SIZE(type);
  if (msg.width == 0 || msg.height == 0) {
    c.error = fmt::format("{} image is empty ({}x{})", what, msg.width, msg.height);
  } else if (msg.step < row || msg.data.size() < static_cast<std::size_t>(msg.step) * msg.height) {
    c.error = fmt::format("{} image {}x{} {}: step {} and {} bytes of data do not hold its pixels", what, msg.width,
                          msg.height, msg.encoding, msg.step, msg.data.size());
  } else if (msg.step % CV_ELEM_SIZE1(type) != 0) {
    c.error = fmt::format("{} image {}: step {} is not a whole number of {}-byte values", what, msg.encoding, msg.step,
                          CV_ELEM_SIZE1(type));
  } else if (msg.is_bigendian && CV_ELEM_SIZE1(type) > 1) {
    c.error = fmt::format("{} image {}: big-endian data is not supported", what, msg.encoding);
  } else {
    c.image = cv::Mat(static_cast<int>(msg.height), static_cast<int>(msg.width), type,
                      const_cast<std::uint8_t*>(msg.data.data()), msg.step);
  }
  return c;
}

std_msgs::ColorRGBA Colour(float r, float g, float b, float a = 1.f) {
  std_msgs::ColorRGBA c;
  c.r = r, c.g = g, c.b = b, c.a = a;
  return c;
}

geometry_msgs::Point Point(double x, double y, double z) {
  geometry_msgs::Point p;
  p.x = x, p.y = y, p.z = z;
  return p;
}

// The 12 edges of the axis-aligned box lo..hi as a LINE_LIST's point pairs.
void AddWireBox(const Eigen::Vector3d& lo, const Eigen::Vector3d& hi, visualization_msgs::Marker& m) {
  const auto corner = [&](int i) {
    return Point(i & 1 ? hi.x() : lo.x(), i & 2 ? hi.y() : lo.y(), i & 4 ? hi.z() : lo.z());
  };
  for (int i = 0; i < 8; ++i) {
    for (int bit : {1, 2, 4}) {
      if ((i & bit) == 0) m.points.push_back(corner(i)), m.points.push_back(corner(i | bit));
    }
  }
}

// The outline (LINE_LIST) of the axis-aligned box lo..hi, lines `width` m wide.
visualization_msgs::Marker WireBox(const std_msgs::Header& header, const std::string& ns, int id,
                                   const Eigen::Vector3d& lo, const Eigen::Vector3d& hi, double width,
                                   const std_msgs::ColorRGBA& colour) {
  visualization_msgs::Marker box;
  box.header = header;
  box.ns = ns;
  box.id = id;
  box.type = visualization_msgs::Marker::LINE_LIST;
  box.action = visualization_msgs::Marker::ADD;
  box.pose.orientation.w = 1;
  box.scale.x = width;
  box.color = colour;
  AddWireBox(lo, hi, box);
  return box;
}

// A text `gap` m above a box made by WireBox (up is -y), `size` m high, in the box's colour.
visualization_msgs::Marker LabelAbove(const visualization_msgs::Marker& box, const std::string& ns,
                                      const Eigen::Vector3d& centre, double top_y, double gap, double size,
                                      std::string text) {
  visualization_msgs::Marker label = box;
  label.ns = ns;
  label.type = visualization_msgs::Marker::TEXT_VIEW_FACING;
  label.points.clear();
  label.pose.position = Point(centre.x(), top_y - gap, centre.z());
  label.scale.z = size;
  label.text = std::move(text);
  return label;
}

// What a marker array starts with so that the markers it no longer holds disappear.
visualization_msgs::Marker DeleteAll(const std::string& frame, const ros::Time& stamp) {
  visualization_msgs::Marker clear;
  clear.header.frame_id = frame;
  clear.header.stamp = stamp;
  clear.action = visualization_msgs::Marker::DELETEALL;
  return clear;
}

std_msgs::ColorRGBA TrackColour(int id, bool lost) {
  const std::array<float, 4> c = sgslam::TrackColour(id, lost);
  return Colour(c[0], c[1], c[2], c[3]);
}

// A colour from blue (low) through green to red (high), t in [0, 1].
std_msgs::ColorRGBA Ramp(float t) {
  t = std::clamp(t, 0.f, 1.f);
  return Colour(std::clamp(2 * t - 0.5f, 0.f, 1.f), 1.f - std::abs(2 * t - 1.f), std::clamp(1.5f - 2 * t, 0.f, 1.f));
}

}  // namespace

Converted ColourToBgr(const sensor_msgs::Image& msg) {
  namespace enc = sensor_msgs::image_encodings;
  int type = 0, code = -1;  // code -1: a plain copy
  if (msg.encoding == enc::BGR8) {
    type = CV_8UC3;
  } else if (msg.encoding == enc::RGB8) {
    type = CV_8UC3, code = cv::COLOR_RGB2BGR;
  } else if (msg.encoding == enc::BGRA8) {
    type = CV_8UC4, code = cv::COLOR_BGRA2BGR;
  } else if (msg.encoding == enc::RGBA8) {
    type = CV_8UC4, code = cv::COLOR_RGBA2BGR;
  } else if (msg.encoding == enc::MONO8) {
    type = CV_8UC1, code = cv::COLOR_GRAY2BGR;
  } else {
    return {cv::Mat(), "colour image encoding '" + msg.encoding + "' is not one of bgr8, rgb8, bgra8, rgba8, mono8"};
  }
  Converted c = Wrap(msg, type, "colour");
  if (!c.error.empty()) return c;
  cv::Mat bgr;
  if (code < 0) {
    bgr = c.image.clone();
  } else {
    cv::cvtColor(c.image, bgr, code);
  }
  c.image = bgr;
  return c;
}

Converted DepthToRaw(const sensor_msgs::Image& msg, double depth_factor) {
  namespace enc = sensor_msgs::image_encodings;
  const bool metres = msg.encoding == enc::TYPE_32FC1;
  if (!metres && msg.encoding != enc::TYPE_16UC1 && msg.encoding != enc::MONO16) {
    return {cv::Mat(), "depth image encoding '" + msg.encoding +
                           "' is not 32FC1 (metres) or 16UC1/mono16 (millimetres): no depth scale can be assumed"};
  }
  Converted c = Wrap(msg, metres ? CV_32FC1 : CV_16UC1, "depth");
  if (!c.error.empty()) return c;
  // Units per metre of the input, and the largest raw value 16 bits hold.
  const double scale = metres ? depth_factor : depth_factor / 1000.0;
  const double max_raw = 65535.0;
  cv::Mat raw(c.image.size(), CV_16UC1);
  for (int y = 0; y < raw.rows; ++y) {
    auto* out = raw.ptr<std::uint16_t>(y);
    if (metres) {
      const float* in = c.image.ptr<float>(y);
      for (int x = 0; x < raw.cols; ++x) {
        const double v = std::isfinite(in[x]) && in[x] > 0 ? std::round(in[x] * scale) : 0.0;
        out[x] = v <= max_raw ? static_cast<std::uint16_t>(v) : 0;
      }
    } else {
      const auto* in = c.image.ptr<std::uint16_t>(y);
      for (int x = 0; x < raw.cols; ++x) {
        const double v = std::round(in[x] * scale);
        out[x] = v <= max_raw ? static_cast<std::uint16_t>(v) : 0;
      }
    }
  }
  c.image = raw;
  return c;
}

std::optional<CameraConfig> CameraFromInfo(const sensor_msgs::CameraInfo& info, const CameraConfig& base,
                                           std::string* error) {
  const auto fail = [&](const std::string& why) {
    if (error) *error = "camera_info: " + why;
    return std::nullopt;
  };
  if (info.width == 0 || info.height == 0) return fail(fmt::format("no image size ({}x{})", info.width, info.height));
  const double fx = info.K[0], fy = info.K[4], cx = info.K[2], cy = info.K[5];
  for (double v : {fx, fy, cx, cy}) {
    if (!std::isfinite(v)) return fail("K holds a value that is not finite");
  }
  if (fx <= 0 || fy <= 0) return fail(fmt::format("focal length fx {} fy {} is not positive (an uncalibrated camera)", fx, fy));
  CameraConfig c = base;
  c.width = static_cast<int>(info.width), c.height = static_cast<int>(info.height);
  c.fx = fx, c.fy = fy, c.cx = cx, c.cy = cy;
  c.k1 = c.k2 = c.p1 = c.p2 = c.k3 = 0;
  if (!info.D.empty()) {
    if (info.distortion_model != "plumb_bob" && info.distortion_model != "rational_polynomial") {
      return fail("distortion model '" + info.distortion_model + "' is not plumb_bob or rational_polynomial");
    }
    if (info.D.size() < 5) return fail(fmt::format("{} distortion coefficients, 5 expected", info.D.size()));
    for (double v : info.D) {
      if (!std::isfinite(v)) return fail("a distortion coefficient is not finite");
    }
    if (info.distortion_model == "rational_polynomial" && (info.D.size() < 8 || info.D[5] != 0 || info.D[6] != 0 || info.D[7] != 0)) {
      return fail("rational_polynomial distortion with k4..k6 set is not supported (OpenCV's five-coefficient model only)");
    }
    c.k1 = info.D[0], c.k2 = info.D[1], c.p1 = info.D[2], c.p2 = info.D[3], c.k3 = info.D[4];
  }
  return c;
}

ros::Time ToRosTime(Timestamp t) {
  ros::Time r;
  r.fromNSec(static_cast<std::uint64_t>(std::max<Timestamp>(t, 0)));
  return r;
}

Timestamp FromRosTime(const ros::Time& t) { return static_cast<Timestamp>(t.toNSec()); }

geometry_msgs::TransformStamped ToTransform(const SE3& T_w_c, const std::string& parent, const std::string& child,
                                            const ros::Time& stamp) {
  geometry_msgs::TransformStamped m;
  m.header.stamp = stamp;
  m.header.frame_id = parent;
  m.child_frame_id = child;
  const Eigen::Vector3d& t = T_w_c.translation();
  const Eigen::Quaterniond& q = T_w_c.quaternion();
  m.transform.translation.x = t.x(), m.transform.translation.y = t.y(), m.transform.translation.z = t.z();
  m.transform.rotation.x = q.x(), m.transform.rotation.y = q.y(), m.transform.rotation.z = q.z();
  m.transform.rotation.w = q.w();
  return m;
}

nav_msgs::Odometry ToOdometry(const SE3& T_w_c, const std::string& parent, const std::string& child,
                              const ros::Time& stamp) {
  const geometry_msgs::TransformStamped tf = ToTransform(T_w_c, parent, child, stamp);
  nav_msgs::Odometry m;
  m.header = tf.header;
  m.child_frame_id = child;
  m.pose.pose.position.x = tf.transform.translation.x;
  m.pose.pose.position.y = tf.transform.translation.y;
  m.pose.pose.position.z = tf.transform.translation.z;
  m.pose.pose.orientation = tf.transform.rotation;
  return m;  // covariances zero: not estimated
}

sensor_msgs::PointCloud2 ToCloud(const std::vector<Eigen::Vector3f>& points, const std::vector<Rgb>* colours,
                                 const std::string& frame, const ros::Time& stamp) {
  sensor_msgs::PointCloud2 m;
  m.header.stamp = stamp;
  m.header.frame_id = frame;
  m.height = 1;
  m.width = static_cast<std::uint32_t>(points.size());
  const char* names[] = {"x", "y", "z", "rgb"};
  const int fields = colours ? 4 : 3;
  for (int i = 0; i < fields; ++i) {
    sensor_msgs::PointField f;
    f.name = names[i];
    f.offset = static_cast<std::uint32_t>(4 * i);
    f.datatype = sensor_msgs::PointField::FLOAT32;
    f.count = 1;
    m.fields.push_back(f);
  }
  m.point_step = static_cast<std::uint32_t>(4 * fields);
  m.row_step = m.point_step * m.width;
  m.is_dense = true;
  m.is_bigendian = false;
  m.data.resize(static_cast<std::size_t>(m.row_step));
  std::uint8_t* out = m.data.data();
  for (std::size_t i = 0; i < points.size(); ++i, out += m.point_step) {
    std::memcpy(out, points[i].data(), 12);
    if (colours) {
      const Rgb& c = (*colours)[i];
      const std::uint32_t packed = (std::uint32_t{c[0]} << 16) | (std::uint32_t{c[1]} << 8) | std::uint32_t{c[2]};
      std::memcpy(out + 12, &packed, 4);
    }
  }
  return m;
}

sensor_msgs::PointCloud2 DenseCloud(const MapSnapshot& map, const std::string& frame, const ros::Time& stamp) {
  std::vector<Eigen::Vector3f> points;
  std::vector<Rgb> colours;
  for (const CloudPiece& piece : map.cloud) {
    if (!piece.points_c) continue;
    const Eigen::Matrix3f R = piece.T_w_c.rotation().cast<float>();
    const Eigen::Vector3f t = piece.T_w_c.translation().cast<float>();
    for (const ColoredPoint& p : *piece.points_c) {
      points.push_back(R * p.p + t);
      colours.push_back(p.rgb);
    }
  }
  return ToCloud(points, &colours, frame, stamp);
}

visualization_msgs::MarkerArray ObjectMarkers(const std::vector<ObjectEstimate>& objects, const std::string& frame,
                                              const ros::Time& stamp) {
  visualization_msgs::MarkerArray array;
  const visualization_msgs::Marker clear = DeleteAll(frame, stamp);
  array.markers.push_back(clear);
  for (const ObjectEstimate& o : objects) {
    if (!o.exported) continue;
    const Eigen::Vector3d lo = o.centroid - o.size / 2, hi = o.centroid + o.size / 2;
    const visualization_msgs::Marker box = WireBox(clear.header, "objects", o.id, lo, hi, 0.01, Colour(0.3f, 0.64f, 1.f));
    array.markers.push_back(box);
    visualization_msgs::Marker label =
        LabelAbove(box, "labels", o.centroid, lo.y(), 0.05, 0.1, ObjectLabel(o));
    label.color = Colour(1.f, 1.f, 1.f);
    array.markers.push_back(label);
  }
  return array;
}

visualization_msgs::MarkerArray MoverMarkers(const std::vector<MoverSnapshot>& movers, const MoverTrails& trails,
                                             const std::string& frame, const ros::Time& stamp) {
  visualization_msgs::MarkerArray array;
  const visualization_msgs::Marker clear = DeleteAll(frame, stamp);
  array.markers.push_back(clear);
  for (const MoverSnapshot& m : movers) {
    if (m.state == movers::TrackState::kTentative) continue;
    const bool lost = m.state == movers::TrackState::kLost;
    const Eigen::Vector3d lo = m.position - m.extent / 2, hi = m.position + m.extent / 2;
    const visualization_msgs::Marker box = WireBox(clear.header, "movers", m.id, lo, hi, 0.02, TrackColour(m.id, lost));
    array.markers.push_back(box);
    const visualization_msgs::Marker label = LabelAbove(box, "mover_labels", m.position, lo.y(), 0.08, 0.12,
                                                        fmt::format("{} {}{}", m.id, m.class_name, lost ? " (lost)" : ""));
    array.markers.push_back(label);
    const MoverTrails::Trail* trail = trails.Of(m.id);
    if (!trail || trail->size() < 2) continue;  // a line strip needs two points
    visualization_msgs::Marker line = box;
    line.ns = "mover_trails";
    line.type = visualization_msgs::Marker::LINE_STRIP;
    line.points.clear();
    for (const auto& sample : *trail) {
      const Eigen::Vector3d& p = sample.second;
      line.points.push_back(Point(p.x(), p.y(), p.z()));
    }
    array.markers.push_back(line);
  }
  return array;
}

visualization_msgs::Marker CellMarker(const std::vector<Eigen::Vector4f>& cells, const std::string& frame,
                                      const ros::Time& stamp) {
  visualization_msgs::Marker m;
  m.header.frame_id = frame;
  m.header.stamp = stamp;
  m.ns = "octomap";
  m.id = 0;
  m.type = visualization_msgs::Marker::CUBE_LIST;
  m.action = visualization_msgs::Marker::ADD;
  m.pose.orientation.w = 1;
  float side = 0.05f, lo = 0, hi = 0;
  if (!cells.empty()) {
    side = cells.front()[3];
    lo = hi = -cells.front().y();
    for (const Eigen::Vector4f& c : cells) lo = std::min(lo, -c.y()), hi = std::max(hi, -c.y());
  }
  m.scale.x = m.scale.y = m.scale.z = side;
  m.color = Colour(1, 1, 1);
  for (const Eigen::Vector4f& c : cells) {
    m.points.push_back(Point(c.x(), c.y(), c.z()));
    m.colors.push_back(Ramp(hi > lo ? (-c.y() - lo) / (hi - lo) : 0.5f));
  }
  return m;
}

sensor_msgs::Image ToImage(const cv::Mat& image, const std::string& encoding, const ros::Time& stamp,
                           const std::string& frame_id) {
  sensor_msgs::Image m;
  m.header.stamp = stamp;
  m.header.frame_id = frame_id;
  m.height = static_cast<std::uint32_t>(image.rows);
  m.width = static_cast<std::uint32_t>(image.cols);
  m.encoding = encoding;
  m.is_bigendian = false;
  m.step = static_cast<std::uint32_t>(image.cols * image.elemSize());
  m.data.resize(static_cast<std::size_t>(m.step) * m.height);
  for (int y = 0; y < image.rows; ++y) {
    std::memcpy(&m.data[static_cast<std::size_t>(y) * m.step], image.ptr(y), m.step);
  }
  return m;
}

sensor_msgs::Image AnnotatedImage(const FrameSnapshot& frame, const std::string& camera_frame) {
  cv::Mat img = frame.bgr.clone();
  const cv::Scalar colours[] = {{0, 200, 0}, {0, 0, 255}, {0, 220, 255}};  // kept, rejected, unjudged (BGR)
  for (std::size_t i = 0; i < frame.keypoints.size(); ++i) {
    const std::uint8_t label = i < frame.labels.size() ? frame.labels[i] : static_cast<std::uint8_t>(FrameSnapshot::kUnjudged);
    cv::circle(img, frame.keypoints[i], 3, colours[std::min<std::uint8_t>(label, 2)], 1, cv::LINE_AA);
  }
  for (const Detection& d : frame.detections) {
    const cv::Scalar c = d.carried ? cv::Scalar(67, 159, 255) : cv::Scalar(255, 163, 77);
    cv::rectangle(img, d.box, c, 2);
    const std::string text = fmt::format("{} {:.2f}{}", d.class_name, d.score, d.carried ? " (carried)" : "");
    cv::putText(img, text, cv::Point(static_cast<int>(d.box.x) + 2, std::max(12, static_cast<int>(d.box.y) - 4)),
                cv::FONT_HERSHEY_SIMPLEX, 0.45, c, 1, cv::LINE_AA);
  }
  return ToImage(img, sensor_msgs::image_encodings::BGR8, ToRosTime(frame.t), camera_frame);
}

}  // namespace sgslam::ros_bridge
