#include "web_stream.h"

#include <algorithm>
#include <cstring>
#include <fstream>
#include <iterator>
#include <optional>

#include "core_handles.h"
#include "file_error.h"
#include "json_value.h"

namespace bakegi::cli {

namespace {

constexpr uint32_t kGridPacket = 1, kGeometryPacket = 2, kVisibilityPacket = 3;

std::vector<uint8_t> read_bytes(const std::filesystem::path& path) {
  std::ifstream file(path, std::ios::binary);
  if (!file) throw FileError(path.string() + ": cannot read it");
  return {std::istreambuf_iterator<char>(file), std::istreambuf_iterator<char>()};
}

const JsonValue& member(const JsonValue& object, const std::string& key, const std::string& where) {
  const JsonValue* value = object.find(key);
  if (!value) throw FileError("scene.gltf: " + where + " has no \"" + key + "\"");
  return *value;
}

const JsonValue::Array& array(const JsonValue& value, const std::string& where) {
  const auto* items = std::get_if<JsonValue::Array>(&value.value);
  if (!items) throw FileError("scene.gltf: " + where + " is not an array");
  return *items;
}

size_t index_of(const JsonValue& value, const std::string& where) {
  const std::optional<double> number = value.number();
  if (!number || *number < 0 || *number != double(size_t(*number))) {
    throw FileError("scene.gltf: " + where + " is not an index");
  }
  return size_t(*number);
}

// The bytes of accessor `index` (tightly packed, as bakegi web export writes them), checked
// against the buffer and the expected element size.
template <typename T>
std::vector<T> accessor_data(const JsonValue& gltf, size_t index, size_t components,
                             const std::vector<uint8_t>& bin) {
  const auto& accessors = array(member(gltf, "accessors", "the file"), "accessors");
  const auto& views = array(member(gltf, "bufferViews", "the file"), "bufferViews");
  if (index >= accessors.size()) throw FileError("scene.gltf: accessor index out of range");
  const JsonValue& accessor = accessors[index];
  const size_t view_index = index_of(member(accessor, "bufferView", "an accessor"), "bufferView");
  const size_t count = index_of(member(accessor, "count", "an accessor"), "count");
  if (view_index >= views.size()) throw FileError("scene.gltf: bufferView index out of range");
  const JsonValue& view = views[view_index];
  const JsonValue* offset_value = view.find("byteOffset");
  const size_t offset = offset_value ? index_of(*offset_value, "byteOffset") : 0;
  const size_t length = index_of(member(view, "byteLength", "a bufferView"), "byteLength");
  if (length != count * components * sizeof(T) || offset + length > bin.size()) {
    throw FileError("scene.gltf: accessor " + std::to_string(index) +
                    " does not match scene.bin (not a bakegi web export?)");
  }
  std::vector<T> data(count * components);
  std::memcpy(data.data(), bin.data() + offset, length);
  return data;
}

struct StreamedPrimitive {
  size_t mesh = 0, primitive = 0, material = 0;
  std::vector<float> positions, normals;  // 3 per vertex; normals empty when flat
  std::vector<float> uvs;                 // 2 per vertex, or empty
  std::vector<float> reads_grid;          // 1 per vertex, or empty (web/corner_grid_reach.h)
  std::vector<uint32_t> faces, parent, valid_at, level_vertices;
  // Streaming state.
  uint32_t vertices_sent = 0;
  size_t faces_sent = 0;
  std::vector<uint8_t> lookup_sent;
};

class PacketWriter {
 public:
  void word(uint32_t value) { append(&value, 4); }
  void append(const void* data, size_t bytes) {
    const auto* p = static_cast<const uint8_t*>(data);
    bytes_.insert(bytes_.end(), p, p + bytes);
  }
  void set_word(size_t at, uint32_t value) { std::memcpy(bytes_.data() + at, &value, 4); }
  size_t size() const { return bytes_.size(); }
  std::vector<uint8_t> take() { return std::move(bytes_); }

 private:
  std::vector<uint8_t> bytes_;
};

// One primitive's share of a geometry packet: vertices [first, first + count), the faces
// valid once they are in, and the lookup entries those faces need.
void write_entry(PacketWriter& out, StreamedPrimitive& p, size_t index, uint32_t count,
                 size_t* faces_written) {
  const uint32_t first = p.vertices_sent;
  const uint32_t n = first + count;
  const size_t face_end =
      size_t(std::upper_bound(p.valid_at.begin(), p.valid_at.end(), n) - p.valid_at.begin());
  std::vector<uint32_t> lookup;
  for (size_t f = p.faces_sent; f < face_end; ++f) {
    for (int c = 0; c < 3; ++c) {
      for (uint32_t v = p.faces[3 * f + c]; v >= n && !p.lookup_sent[v]; v = p.parent[v]) {
        p.lookup_sent[v] = 1;
        lookup.insert(lookup.end(), {v, p.parent[v]});
      }
    }
  }
  const bool has_normals = !p.normals.empty(), has_uvs = !p.uvs.empty();
  const bool has_reads_grid = !p.reads_grid.empty();
  for (const uint32_t word :
       {uint32_t(index), first, count, uint32_t(has_normals), uint32_t(has_uvs),
        uint32_t(has_reads_grid), uint32_t(face_end - p.faces_sent), uint32_t(lookup.size() / 2)}) {
    out.word(word);
  }
  out.append(p.positions.data() + 3 * size_t(first), 12 * size_t(count));
  if (has_normals) out.append(p.normals.data() + 3 * size_t(first), 12 * size_t(count));
  if (has_uvs) out.append(p.uvs.data() + 2 * size_t(first), 8 * size_t(count));
  if (has_reads_grid) out.append(p.reads_grid.data() + size_t(first), 4 * size_t(count));
  out.append(p.faces.data() + 3 * p.faces_sent, 12 * (face_end - p.faces_sent));
  out.append(lookup.data(), 4 * lookup.size());
  *faces_written += face_end - p.faces_sent;
  p.vertices_sent = n;
  p.faces_sent = face_end;
}

}  // namespace

SceneStream::SceneStream(const std::filesystem::path& folder, const StreamSettings& settings) {
  if (settings.vectors_per_request == 0 || settings.vertices_per_packet == 0) {
    throw FileError("packets must carry at least one vector and one vertex");
  }
  const std::vector<uint8_t> json_bytes = read_bytes(folder / "scene.gltf");
  const JsonValue gltf = JsonValue::parse(std::string(json_bytes.begin(), json_bytes.end()));
  const std::vector<uint8_t> bin = read_bytes(folder / "scene.bin");

  // The primitives with their progressive data.
  std::vector<StreamedPrimitive> primitives;
  const JsonValue* meshes = gltf.find("meshes");
  for (size_t m = 0; meshes && m < array(*meshes, "meshes").size(); ++m) {
    const JsonValue& mesh = array(*meshes, "meshes")[m];
    const auto& list = array(member(mesh, "primitives", "a mesh"), "primitives");
    for (size_t i = 0; i < list.size(); ++i) {
      const JsonValue& primitive = list[i];
      const JsonValue* progressive = primitive.find_path({"extras", "bakegi_progressive"});
      if (!progressive) {
        throw FileError(
            "scene.gltf: a primitive has no progressive mesh (write the folder "
            "with bakegi web export)");
      }
      StreamedPrimitive p;
      p.mesh = m, p.primitive = i;
      p.material = index_of(member(primitive, "material", "a primitive"), "material");
      const JsonValue& attributes = member(primitive, "attributes", "a primitive");
      p.positions = accessor_data<float>(
          gltf, index_of(member(attributes, "POSITION", "attributes"), "POSITION"), 3, bin);
      if (const JsonValue* normal = attributes.find("NORMAL")) {
        p.normals = accessor_data<float>(gltf, index_of(*normal, "NORMAL"), 3, bin);
      }
      if (const JsonValue* uv = attributes.find("TEXCOORD_0")) {
        p.uvs = accessor_data<float>(gltf, index_of(*uv, "TEXCOORD_0"), 2, bin);
      }
      if (const JsonValue* reads = attributes.find("_BAKEGI_READS_GRID")) {
        p.reads_grid = accessor_data<float>(gltf, index_of(*reads, "_BAKEGI_READS_GRID"), 1, bin);
      }
      p.faces = accessor_data<uint32_t>(
          gltf, index_of(member(primitive, "indices", "a primitive"), "indices"), 1, bin);
      p.parent = accessor_data<uint32_t>(
          gltf, index_of(member(*progressive, "parent", "bakegi_progressive"), "parent"), 1, bin);
      p.valid_at = accessor_data<uint32_t>(
          gltf, index_of(member(*progressive, "valid_at", "bakegi_progressive"), "valid_at"), 1,
          bin);
      for (const JsonValue& n :
           array(member(*progressive, "level_vertices", "bakegi_progressive"), "levels")) {
        p.level_vertices.push_back(uint32_t(index_of(n, "level_vertices")));
      }
      const size_t vertex_count = p.positions.size() / 3;
      if (p.parent.size() != vertex_count || p.valid_at.size() * 3 != p.faces.size() ||
          p.level_vertices.empty() || p.level_vertices.back() != vertex_count ||
          !(p.normals.empty() || p.normals.size() == p.positions.size()) ||
          !(p.uvs.empty() || p.uvs.size() * 3 == p.positions.size() * 2) ||
          !(p.reads_grid.empty() || p.reads_grid.size() * 3 == p.positions.size())) {
        throw FileError("scene.gltf: a primitive's progressive mesh does not add up");
      }
      for (size_t v = 0; v < vertex_count; ++v) {
        if (p.parent[v] > v) throw FileError("scene.gltf: a vertex collapses onto a later one");
      }
      for (const uint32_t v : p.faces) {
        if (v >= vertex_count) throw FileError("scene.gltf: a face indexes past its vertices");
      }
      p.lookup_sent.assign(vertex_count, 0);
      primitives.push_back(std::move(p));
    }
  }

  // Geometry packets: every primitive's level 0, then level 1, ..., cut every
  // vertices_per_packet vertices.
  std::vector<std::vector<uint8_t>> geometry;
  std::vector<std::string> geometry_rows;
  size_t levels = 0;
  for (const auto& p : primitives) levels = std::max(levels, p.level_vertices.size());
  {
    PacketWriter out;
    uint32_t entries = 0, vertices = 0;
    size_t faces = 0;
    auto start = [&] {
      out = PacketWriter();
      out.word(kGeometryPacket);
      out.word(0);  // entries, set when the packet is closed
      entries = 0, vertices = 0, faces = 0;
    };
    auto close = [&] {
      if (entries == 0) return;
      out.set_word(4, entries);
      geometry_rows.push_back("{\"kind\":\"geometry\",\"vertices\":" + std::to_string(vertices) +
                              ",\"faces\":" + std::to_string(faces) +
                              ",\"bytes\":" + std::to_string(out.size()) + "}");
      geometry.push_back(out.take());
      start();
    };
    start();
    for (size_t level = 0; level < levels; ++level) {
      for (size_t i = 0; i < primitives.size(); ++i) {
        StreamedPrimitive& p = primitives[i];
        // Levels counted from each primitive's coarsest.
        const uint32_t end = p.level_vertices[std::min(level, p.level_vertices.size() - 1)];
        while (p.vertices_sent < end) {
          const uint32_t count =
              std::min(end - p.vertices_sent, settings.vertices_per_packet - vertices);
          write_entry(out, p, i, count, &faces);
          ++entries;
          vertices += count;
          if (vertices == settings.vertices_per_packet) close();
        }
      }
    }
    close();
  }

  // Grid packets: the corners, then vectors_per_request at a time.
  std::vector<std::vector<uint8_t>> grid_packets;
  std::vector<std::string> grid_rows;
  std::string grid_json = "null";
  bool has_visibility = false;
  const JsonValue* grid_name = gltf.find_path({"extras", "bakegi", "grid"});
  if (grid_name && grid_name->string()) {
    const std::filesystem::path grid_path = folder / *grid_name->string();
    bakegi_grid* raw = nullptr;
    check(bakegi_grid_read_file(grid_path.string().c_str(), &raw), "reading " + grid_path.string());
    const GridHandle grid(raw);
    bakegi_grid_info info{};
    check(bakegi_grid_get_info(grid.get(), &info), "the grid's info");
    std::vector<uint32_t> order(info.vertex_count);
    check(bakegi_grid_stream_order(grid.get(), 1, order.data()), "the grid's stream order");
    const int encoding = settings.quantized ? BAKEGI_GRID_QUANTIZED : BAKEGI_GRID_FACTORED;
    const size_t record = settings.quantized ? 42 : 144;
    for (size_t first = 0; first < order.size();) {
      const size_t count =
          std::min<size_t>(first == 0 ? 8 : settings.vectors_per_request, order.size() - first);
      PacketWriter out;
      out.word(kGridPacket);
      out.word(uint32_t(count));
      out.word(uint32_t(encoding));
      out.append(order.data() + first, 4 * count);
      std::vector<uint8_t> records(record * count);
      check(bakegi_grid_encode_vertices(grid.get(), order.data() + first, count, encoding,
                                        records.data()),
            "encoding the grid's vectors");
      out.append(records.data(), records.size());
      grid_rows.push_back("{\"kind\":\"grid\",\"vectors\":" + std::to_string(count) +
                          ",\"bytes\":" + std::to_string(out.size()) + "}");
      grid_packets.push_back(out.take());
      first += count;
    }
    // The page's visibility volume right after the corners: the page reads the grid through
    // walls until it has it.
    const JsonValue* visibility_name = gltf.find_path({"extras", "bakegi", "grid_visibility"});
    if (visibility_name && visibility_name->string()) {
      const std::vector<uint8_t> file = read_bytes(folder / *visibility_name->string());
      PacketWriter out;
      out.word(kVisibilityPacket);
      out.word(uint32_t(file.size()));
      out.append(file.data(), file.size());
      while (out.size() % 4) out.append("", 1);
      grid_rows.insert(grid_rows.begin() + 1,
                       "{\"kind\":\"visibility\",\"bytes\":" + std::to_string(out.size()) + "}");
      grid_packets.insert(grid_packets.begin() + 1, out.take());
      has_visibility = true;
    }
    grid_json = "{\"file\":" + json_quote(*grid_name->string()) + ",\"resolution\":[" +
                std::to_string(info.resolution[0]) + "," + std::to_string(info.resolution[1]) +
                "," + std::to_string(info.resolution[2]) + "],\"bounds_min\":[" +
                json_number(info.bounds_min[0]) + "," + json_number(info.bounds_min[1]) + "," +
                json_number(info.bounds_min[2]) + "],\"bounds_max\":[" +
                json_number(info.bounds_max[0]) + "," + json_number(info.bounds_max[1]) + "," +
                json_number(info.bounds_max[2]) +
                "],\"vertex_count\":" + std::to_string(info.vertex_count) + ",\"encoding\":\"" +
                (settings.quantized ? "quantized" : "factored") +
                "\",\"bytes_per_vector\":" + std::to_string(record) +
                ",\"visibility\":" + (has_visibility ? "true" : "false") + "}";
  }

  // Interleaved: grid, geometry, grid, geometry, ... (§4: the smoothest progression).
  std::string rows;
  size_t total = 0;
  for (size_t i = 0; i < std::max(grid_packets.size(), geometry.size()); ++i) {
    for (auto [packets, descriptions] :
         {std::pair{&grid_packets, &grid_rows}, std::pair{&geometry, &geometry_rows}}) {
      if (i >= packets->size()) continue;
      if (!rows.empty()) rows += ',';
      rows += (*descriptions)[i];
      total += (*packets)[i].size();
      packets_.push_back(std::move((*packets)[i]));
    }
  }
  std::string primitive_rows;
  for (const auto& p : primitives) {
    if (!primitive_rows.empty()) primitive_rows += ',';
    primitive_rows += "{\"mesh\":" + std::to_string(p.mesh) +
                      ",\"primitive\":" + std::to_string(p.primitive) +
                      ",\"material\":" + std::to_string(p.material) +
                      ",\"vertex_count\":" + std::to_string(p.positions.size() / 3) +
                      ",\"face_count\":" + std::to_string(p.valid_at.size()) +
                      ",\"has_normals\":" + (p.normals.empty() ? "false" : "true") +
                      ",\"has_uvs\":" + (p.uvs.empty() ? "false" : "true") +
                      ",\"has_reads_grid\":" + (p.reads_grid.empty() ? "false" : "true") + "}";
  }
  manifest_ = "{\"format\":1,\"gltf\":\"scene.gltf\",\"grid\":" + grid_json +
              ",\"vectors_per_request\":" + std::to_string(settings.vectors_per_request) +
              ",\"vertices_per_packet\":" + std::to_string(settings.vertices_per_packet) +
              ",\"primitives\":[" + primitive_rows + "],\"packets\":[" + rows +
              "],\"total_bytes\":" + std::to_string(total) + "}";
}

}  // namespace bakegi::cli
