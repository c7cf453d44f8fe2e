#include "sgslam/mapfile/map_file.h"

#include <unistd.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstring>
#include <sstream>
#include <streambuf>
#include <string_view>

#include <Eigen/Core>
#include <cereal/archives/portable_binary.hpp>
#include <cereal/types/array.hpp>
#include <cereal/types/utility.hpp>

#include "sgslam/common/error.h"
#include "sgslam/common/regular_file.h"
#include "sgslam/common/sha256.h"
#include "sgslam/io/atomic_write.h"
#include "sgslam/mapfile/map_check.h"

namespace sgslam::mapfile {
namespace {

// The payload being decoded: a crafted element count must not allocate far more
// than the bytes left could hold (cereal's own vector and string loaders resize first).
thread_local const std::istream* g_payload = nullptr;
thread_local std::size_t g_payload_size = 0;
// The format version of the file being decoded (0: encoding): version 1 files are
// read too (their objects' class and box are left: Restore derives them).
thread_local std::uint32_t g_reading_version = 0;

// Throws when n elements of `bytes` bytes each (in memory) cannot come from the
// bytes left: an arithmetic element takes its size in the stream, any other at least
// an eighth of its size in memory (a size tag and its fields).
void CheckCount(std::uint64_t n, std::size_t bytes, bool arithmetic) {
  if (!g_payload) return;  // encoding
  const auto at = static_cast<std::size_t>(const_cast<std::istream*>(g_payload)->tellg());
  const std::size_t left = at <= g_payload_size ? g_payload_size - at : 0;
  const double need = static_cast<double>(n) * static_cast<double>(bytes) / (arithmetic ? 1.0 : 8.0);
  if (need > static_cast<double>(left)) throw std::length_error("a count larger than the data left");
}

}  // namespace
}  // namespace sgslam::mapfile

// std::vector and std::string for cereal, as its own (types/vector.hpp,
// types/string.hpp), with CheckCount before allocating; this file includes neither.
// And bool, checked.
namespace cereal {
template <class Archive, class T, class A>
void CEREAL_SAVE_FUNCTION_NAME(Archive& ar, const std::vector<T, A>& v) {
  static_assert(!std::is_same_v<T, bool>);
  ar(make_size_tag(static_cast<size_type>(v.size())));
  if constexpr (std::is_arithmetic_v<T>) {
    ar(binary_data(v.data(), v.size() * sizeof(T)));
  } else {
    for (const auto& x : v) ar(x);
  }
}
template <class Archive, class T, class A>
void CEREAL_LOAD_FUNCTION_NAME(Archive& ar, std::vector<T, A>& v) {
  size_type n = 0;
  ar(make_size_tag(n));
  sgslam::mapfile::CheckCount(n, sizeof(T), std::is_arithmetic_v<T>);
  v.resize(static_cast<std::size_t>(n));
  if constexpr (std::is_arithmetic_v<T>) {
    ar(binary_data(v.data(), v.size() * sizeof(T)));
  } else {
    for (auto& x : v) ar(x);
  }
}
// A bool is one byte in the file; a byte other than 0 or 1 is corrupt, and copying
// it into a bool, as cereal's own loader does, is undefined behaviour.
inline void CEREAL_LOAD_FUNCTION_NAME(PortableBinaryInputArchive& ar, bool& b) {
  std::uint8_t byte = 0;
  ar(byte);
  if (byte > 1) throw Exception("a true/false byte of value " + std::to_string(byte));
  b = byte == 1;
}
template <class Archive>
void CEREAL_SAVE_FUNCTION_NAME(Archive& ar, const std::string& s) {
  ar(make_size_tag(static_cast<size_type>(s.size())));
  ar(binary_data(s.data(), s.size()));
}
template <class Archive>
void CEREAL_LOAD_FUNCTION_NAME(Archive& ar, std::string& s) {
  size_type n = 0;
  ar(make_size_tag(n));
  sgslam::mapfile::CheckCount(n, 1, true);
  s.resize(static_cast<std::size_t>(n));
  ar(binary_data(s.data(), s.size()));
}
}  // namespace cereal

namespace sgslam::mapfile {

// cereal finds these by argument-dependent lookup.
template <class A>
void serialize(A& ar, Pose& p) {
  ar(p.q, p.t);
}
template <class A>
void serialize(A& ar, KeyPointData& k) {
  ar(k.x, k.y, k.size, k.angle, k.response, k.octave);
}
template <class A>
void serialize(A& ar, DetectionData& d) {
  ar(d.class_id, d.class_name, d.score, d.box, d.carried);
}
template <class A>
void serialize(A& ar, ImageData& i) {
  ar(i.rows, i.cols, i.pixels);
}
template <class A>
void serialize(A& ar, KeyFrameData& k) {
  ar(k.id, k.frame_id, k.t, k.T_c_w, k.culled, k.parent, k.T_c_parent);
  ar(k.keys, k.keys_un, k.depth, k.u_right, k.descriptors, k.dynamic, k.unjudged, k.detections, k.angular_velocity);
  ar(k.has_bow, k.bow_words, k.bow_nodes, k.point_ids, k.connections, k.covisible_order, k.loop_edges);
}
template <class A>
void serialize(A& ar, MapPointData& p) {
  ar(p.id, p.first_keyframe_id, p.created_t, p.position, p.normal, p.descriptor, p.min_distance, p.max_distance,
     p.visible, p.found, p.reference, p.observations);
}
template <class A>
void serialize(A& ar, ColoredPointData& p) {
  ar(p.p, p.rgb);
}
template <class A>
void serialize(A& ar, CloudData& c) {
  ar(c.keyframe, c.points_c, c.rays_c, c.depth_pooled, c.moving_pooled);
}
template <class A>
void serialize(A& ar, ObjectObservationData& o) {
  ar(o.keyframe, o.class_id, o.class_name, o.score, o.box, o.T_w_c_added, o.points_c, o.cut);
}
template <class A>
void serialize(A& ar, ObjectData& o) {
  if (g_reading_version == 1) {
    // Version 1 kept the winning class and the box, which follow from the
    // observations, and no views' counts.
    std::int32_t class_id = -1;
    std::string class_name;
    std::array<double, 3> box_min{}, box_max{};
    ar(o.id, class_id, class_name, o.observations, box_min, box_max);
    return;
  }
  ar(o.id, o.observations, o.views_expected, o.views_seen, o.missing);
}
template <class A>
void serialize(A& ar, SemanticData& s) {
  ar(s.present, s.clouds, s.objects, s.next_object_id);
}
template <class A>
void serialize(A& ar, Settings& s) {
  s.camera.Visit([&](const char*, auto& value, const char*) { ar(value); });
  ar(s.orb_scale_factor, s.orb_levels, s.vocabulary_checksum);
}
template <class A>
void serialize(A& ar, MapData& m) {
  ar(m.created, m.settings, m.next_keyframe_id, m.next_point_id, m.next_frame_id, m.keyframes, m.points, m.semantic);
}

static_assert(std::endian::native == std::endian::little, "the map file's header is read and written little-endian");

namespace {

constexpr std::size_t kHeaderBytes = kFileMagic.size() + 4 + 8 + 32;

std::string RawFromHex(const std::string& hex) {
  std::string raw(32, '\0');
  for (std::size_t i = 0; i < 32; ++i) raw[i] = static_cast<char>(std::stoi(hex.substr(2 * i, 2), nullptr, 16));
  return raw;
}

std::string Sha256Bytes(const std::string& bytes) { return RawFromHex(Sha256Hex(bytes)); }

}  // namespace

std::string Encode(const MapData& data) {
  std::ostringstream payload_stream(std::ios::binary);
  {
    cereal::PortableBinaryOutputArchive ar(payload_stream);
    ar(const_cast<MapData&>(data));  // cereal's serialize() is one function for both directions
  }
  const std::string payload = payload_stream.str();
  std::string out(kFileMagic);
  const std::uint32_t version = kFormatVersion;
  const std::uint64_t size = payload.size();
  out.append(reinterpret_cast<const char*>(&version), sizeof version);
  out.append(reinterpret_cast<const char*>(&size), sizeof size);
  out += Sha256Bytes(payload);
  out += payload;
  return out;
}

namespace {

struct Header {
  std::uint32_t version = 0;
  std::uint64_t payload_bytes = 0;
  std::string checksum;  // SHA-256 of the payload, 32 raw bytes
};

// The header's magic and version; `bytes` holds the header, `file_bytes` is the
// whole file's size, which must be the header's and the payload's it gives.
Header ParseHeader(std::string_view bytes, std::uint64_t file_bytes, const std::string& what) {
  if (file_bytes < kHeaderBytes) FailMapFile(what, "too short for a map file (" + std::to_string(file_bytes) + " bytes)");
  if (bytes.substr(0, kFileMagic.size()) != kFileMagic) FailMapFile(what, "not an sgslam map file (wrong magic)");
  std::uint32_t version = 0;
  Header h;
  std::memcpy(&version, bytes.data() + 8, sizeof version);
  std::memcpy(&h.payload_bytes, bytes.data() + 12, sizeof h.payload_bytes);
  if (version < kOldestFormatVersion || version > kFormatVersion) {
    FailMapFile(what, "format version " + std::to_string(version) + "; this sgslam reads versions " +
                   std::to_string(kOldestFormatVersion) + " to " + std::to_string(kFormatVersion));
  }
  h.version = version;
  if (h.payload_bytes != file_bytes - kHeaderBytes) {
    FailMapFile(what, "truncated or padded: the header says " + std::to_string(h.payload_bytes) +
                   " payload bytes, the file has " + std::to_string(file_bytes - kHeaderBytes));
  }
  h.checksum = std::string(bytes.substr(20, 32));
  return h;
}

// The payload as a stream without a copy (cereal reads an istream; CheckCount asks
// where it is).
class PayloadBuffer : public std::streambuf {
 public:
  explicit PayloadBuffer(const std::string& bytes) {
    char* begin = const_cast<char*>(bytes.data());  // only ever read
    setg(begin, begin, begin + bytes.size());
  }

 protected:
  pos_type seekoff(off_type off, std::ios_base::seekdir dir, std::ios_base::openmode) override {
    if (off != 0 || dir != std::ios_base::cur) return pos_type(off_type(-1));
    return pos_type(gptr() - eback());
  }
};

[[noreturn]] void ChecksumMismatch(const std::string& what) { FailMapFile(what, "checksum mismatch (the file is corrupt)"); }

// The payload, whose checksum the caller has checked.
MapData DecodePayload(const std::string& payload, std::uint32_t version, const std::string& what) {
  MapData data;
  try {
    PayloadBuffer buffer(payload);
    std::istream in(&buffer);
    g_payload = &in;
    g_payload_size = payload.size();
    g_reading_version = version;
    struct Reset {
      ~Reset() {
        g_payload = nullptr;
        g_reading_version = 0;
      }
    } reset;
    cereal::PortableBinaryInputArchive ar(in);
    ar(data);
    if (in.peek() != std::char_traits<char>::eof()) FailMapFile(what, "bytes left over after the map (corrupt)");
  } catch (const InputError&) {
    throw;
  } catch (const std::exception& e) {  // cereal::Exception, or a size that cannot be allocated
    FailMapFile(what, std::string("cannot decode the map (corrupt): ") + e.what());
  }
  CheckMapData(data, what);
  return data;
}

}  // namespace

MapData Decode(const std::string& bytes, const std::string& what) {
  const Header h = ParseHeader(bytes, bytes.size(), what);
  std::string payload = bytes.substr(kHeaderBytes);
  if (Sha256Bytes(payload) != h.checksum) ChecksumMismatch(what);
  return DecodePayload(payload, h.version, what);
}

void WriteMapFile(const std::filesystem::path& path, const MapData& data) {
  WriteFileAtomically(path, Encode(data));
}

MapData ReadMapFile(const std::filesystem::path& path) {
  // The header first: a file of the wrong kind, or whose header does not fit its
  // size, is refused after reading 52 bytes, not after reading gigabytes.
  const RegularFile file(path, "map file");
  const std::string header = file.Read(0, static_cast<std::size_t>(std::min<std::uint64_t>(kHeaderBytes, file.size())));
  const Header h = ParseHeader(header, file.size(), path.string());
  // Decoding holds the payload and the map it makes: a payload beyond the
  // machine's memory can only end in std::bad_alloc, or in swapping for minutes.
  const long pages = sysconf(_SC_PHYS_PAGES), page = sysconf(_SC_PAGESIZE);
  if (pages > 0 && page > 0 && h.payload_bytes > static_cast<std::uint64_t>(pages) * static_cast<std::uint64_t>(page)) {
    FailMapFile(path.string(), std::to_string(h.payload_bytes) + " bytes of map, more than this machine's memory");
  }
  // The checksum before the payload is held: a header that fits the file's size
  // says nothing of what follows it (gigabytes of zeros, say).
  if (RawFromHex(Sha256HexOfFile(file, kHeaderBytes, h.payload_bytes)) != h.checksum) ChecksumMismatch(path.string());
  return DecodePayload(file.Read(kHeaderBytes, static_cast<std::size_t>(h.payload_bytes)), h.version, path.string());
}

std::string Describe(const MapData& d) {
  std::size_t live = 0, culled = 0, cloud_points = 0;
  Eigen::Vector3d lo = Eigen::Vector3d::Constant(INFINITY), hi = -lo;
  for (const KeyFrameData& k : d.keyframes) (k.culled ? culled : live) += 1;
  for (const MapPointData& p : d.points) {
    const Eigen::Vector3d x(p.position[0], p.position[1], p.position[2]);
    lo = lo.cwiseMin(x);
    hi = hi.cwiseMax(x);
  }
  for (const CloudData& c : d.semantic.clouds) cloud_points += c.points_c.size();
  const CameraConfig& c = d.settings.camera;
  std::ostringstream o;
  o.setf(std::ios::fixed);
  o.precision(1);
  o << "format version " << kFormatVersion << ", saved " << d.created << "\n";
  o << "camera " << c.width << "x" << c.height << ", fx " << c.fx << " fy " << c.fy << " cx " << c.cx << " cy "
    << c.cy << ", depth factor " << c.depth_factor << "\n";
  o << "ORB: " << d.settings.orb_levels << " levels, scale " << d.settings.orb_scale_factor << "; vocabulary "
    << (d.settings.vocabulary_checksum.empty() ? "none" : d.settings.vocabulary_checksum.substr(0, 16) + "...") << "\n";
  o << "keyframes " << live << " (and " << culled << " culled, kept as anchors of the semantic map), map points "
    << d.points.size() << "\n";
  if (!d.points.empty()) {
    o.precision(2);
    const Eigen::Vector3d e = hi - lo;
    o << "points span " << e.x() << " x " << e.y() << " x " << e.z() << " m\n";
  }
  if (d.semantic.present) {
    o << "semantic map: " << d.semantic.clouds.size() << " keyframe clouds (" << cloud_points << " points), "
      << d.semantic.objects.size() << " objects\n";
  } else {
    o << "semantic map: none (saved without semantic.enabled)\n";
  }
  return o.str();
}

std::vector<std::pair<std::string, double>> CameraValues(CameraConfig camera) {
  std::vector<std::pair<std::string, double>> out;
  camera.Visit([&](const char* name, auto& v, const char*) { out.emplace_back(name, static_cast<double>(v)); });
  return out;
}

bool SameContent(const MapData& a, const MapData& b) {
  return CameraValues(a.settings.camera) == CameraValues(b.settings.camera) && a.settings.orb_scale_factor == b.settings.orb_scale_factor &&
         a.settings.orb_levels == b.settings.orb_levels &&
         a.settings.vocabulary_checksum == b.settings.vocabulary_checksum && a.next_keyframe_id == b.next_keyframe_id &&
         a.next_point_id == b.next_point_id && a.next_frame_id == b.next_frame_id && a.keyframes == b.keyframes &&
         a.points == b.points && a.semantic == b.semantic;
}

}  // namespace sgslam::mapfile
