#include "sim/mesh/msh_reader.h"

#include <array>
#include <cmath>
#include <unordered_map>
#include <vector>

#include "sim/mesh/mesh_from_file_data.h"
#include "sim/mesh/mesh_text_reader.h"

namespace incise::sim {
namespace {

constexpr long long kTetrahedronType = 4;  // gmsh element type of the 4-node tetrahedron

// What the sections hold, before node tags are resolved: sections may come in any order.
struct MshContent {
  int version = 0;  // 2 (for 2.2) or 4 (for 4.1)
  std::vector<long long> node_tags;
  std::vector<Vec3> node_positions;
  std::vector<int> node_lines;
  std::vector<std::array<long long, 4>> tet_nodes;
  std::vector<int> tet_lines;
  std::vector<long long> tet_tags;   // 2.2: the physical tag; 4.1: the volume entity tag
  std::vector<int> tet_block_lines;  // 4.1: the line of the tet's element block
  bool has_entities = false;
  std::unordered_map<long long, long long> volume_physical_tag;  // 4.1 $Entities
};

// Reads the next record line of a section that declared count records; a section end before
// them is a bad count, the end of the file a truncation.
void expect_record(MeshTextReader& in, std::string_view what, int index, int count,
                   std::string_view section) {
  if (!in.next_line()) {
    in.fail_truncated(std::string(what) + " " + std::to_string(index + 1) + " of " +
                      std::to_string(count));
  }
  if (in.token(0).front() == '$') {
    in.fail("bad count: " + std::string(section) + " declares " + std::to_string(count) + " " +
            std::string(what) + "s but " + std::string(in.token(0)) + " follows " +
            std::to_string(index));
  }
}

void expect_end(MeshTextReader& in, const std::string& section, const std::string& records) {
  const std::string end = "$End" + section.substr(1);
  in.expect_line(end);
  if (in.token(0) != end) {
    in.fail("bad count: expected " + end + " after " + records + ", found '" +
            std::string(in.token(0)) + "'");
  }
}

void read_node_position(const MeshTextReader& in, std::size_t first, MshContent& content) {
  // The tag is read before the position in both versions.
  const long long tag = content.node_tags[content.node_positions.size()];
  content.node_positions.emplace_back(in.real(first, {"node ", tag, " x"}),
                                      in.real(first + 1, {"node ", tag, " y"}),
                                      in.real(first + 2, {"node ", tag, " z"}));
  content.node_lines.push_back(in.line_number());
}

void read_tet_nodes(const MeshTextReader& in, std::size_t first, MshContent& content) {
  std::array<long long, 4> nodes{};
  for (int k = 0; k < 4; ++k) {
    nodes[k] = in.integer(first + k, {"tetrahedron node ", k + 1, ""});
  }
  content.tet_nodes.push_back(nodes);
  content.tet_lines.push_back(in.line_number());
}

void read_nodes_v2(MeshTextReader& in, MshContent& content) {
  in.expect_line("the node count");
  const int count = in.count(0, "the node count");
  for (int i = 0; i < count; ++i) {
    expect_record(in, "node", i, count, "$Nodes");
    in.expect_exactly(4, "node (tag x y z)");
    content.node_tags.push_back(in.integer(0, "node tag"));
    read_node_position(in, 1, content);
  }
  expect_end(in, "$Nodes", std::to_string(count) + " nodes (the declared count)");
}

void read_elements_v2(MeshTextReader& in, MshContent& content) {
  in.expect_line("the element count");
  const int count = in.count(0, "the element count");
  for (int i = 0; i < count; ++i) {
    expect_record(in, "element", i, count, "$Elements");
    in.expect_at_least(3, "element (tag type #tags ...)");
    in.integer(0, "element tag");
    if (in.integer(1, "element type") != kTetrahedronType) continue;
    const int tags = in.count(2, "the element's tag count");
    in.expect_exactly(3 + static_cast<std::size_t>(tags) + 4, {"tetrahedron with ", tags, " tags"});
    content.tet_tags.push_back(tags > 0 ? in.integer(3, "physical tag") : 0);
    read_tet_nodes(in, 3 + static_cast<std::size_t>(tags), content);
  }
  expect_end(in, "$Elements", std::to_string(count) + " elements (the declared count)");
}

void read_entities_v4(MeshTextReader& in, MshContent& content) {
  in.expect_line("the entity counts");
  in.expect_exactly(4, "entity counts (#points #curves #surfaces #volumes)");
  int lower_entities = 0;
  for (int dim = 0; dim < 3; ++dim)
    lower_entities += in.count(dim, "an entity count");
  const int volumes = in.count(3, "the volume count");
  for (int i = 0; i < lower_entities; ++i)
    expect_record(in, "entity", i, lower_entities, "$Entities");
  for (int i = 0; i < volumes; ++i) {
    expect_record(in, "volume", i, volumes, "$Entities");
    in.expect_at_least(8, "volume entity (tag box #physical tags ...)");
    const int physical = in.count(7, "the volume's physical tag count");
    in.expect_at_least(8 + static_cast<std::size_t>(physical),
                       "volume entity with " + std::to_string(physical) + " physical tags");
    content.volume_physical_tag[in.integer(0, "volume tag")] =
        physical > 0 ? in.integer(8, "physical tag") : 0;
  }
  content.has_entities = true;
  expect_end(in, "$Entities", "the declared entities");
}

void read_nodes_v4(MeshTextReader& in, MshContent& content) {
  in.expect_line("the node block header");
  in.expect_exactly(4, "nodes header (#blocks #nodes min tag max tag)");
  const int blocks = in.count(0, "the node block count");
  const int count = in.count(1, "the node count");
  const int header_line = in.line_number();
  int read = 0;
  for (int b = 0; b < blocks; ++b) {
    expect_record(in, "node block", b, blocks, "$Nodes");
    in.expect_exactly(4, "node block (entity dim, entity tag, parametric, #nodes)");
    const long long dim = in.integer(0, "entity dimension");
    const bool parametric = in.integer(2, "parametric flag") != 0;
    const int block_count = in.count(3, "the block's node count");
    if (block_count > count - read) {
      in.fail("bad count: node blocks hold more than the " + std::to_string(count) +
              " nodes declared");
    }
    for (int i = 0; i < block_count; ++i) {
      expect_record(in, "node tag", read + i, count, "$Nodes");
      in.expect_exactly(1, "node tag");
      content.node_tags.push_back(in.integer(0, "node tag"));
    }
    const std::size_t fields = 3 + (parametric ? static_cast<std::size_t>(dim) : 0);
    for (int i = 0; i < block_count; ++i) {
      expect_record(in, "node coordinate line", read + i, count, "$Nodes");
      in.expect_exactly(fields, parametric ? "node (x y z u...)" : "node (x y z)");
      read_node_position(in, 0, content);
    }
    read += block_count;
  }
  if (read != count) {
    in.fail_at(header_line, "bad count: $Nodes declares " + std::to_string(count) +
                                " nodes, its blocks hold " + std::to_string(read));
  }
  expect_end(in, "$Nodes", std::to_string(blocks) + " node blocks (the declared count)");
}

void read_elements_v4(MeshTextReader& in, MshContent& content) {
  in.expect_line("the element block header");
  in.expect_exactly(4, "elements header (#blocks #elements min tag max tag)");
  const int blocks = in.count(0, "the element block count");
  const int count = in.count(1, "the element count");
  const int header_line = in.line_number();
  int read = 0;
  for (int b = 0; b < blocks; ++b) {
    expect_record(in, "element block", b, blocks, "$Elements");
    in.expect_exactly(4, "element block (entity dim, entity tag, type, #elements)");
    const long long dim = in.integer(0, "entity dimension");
    const long long entity = in.integer(1, "entity tag");
    const long long type = in.integer(2, "element type");
    const int block_count = in.count(3, "the block's element count");
    const int block_line = in.line_number();
    if (block_count > count - read) {
      in.fail("bad count: element blocks hold more than the " + std::to_string(count) +
              " elements declared");
    }
    if (type == kTetrahedronType && dim != 3) {
      in.fail("tetrahedra in an entity of dimension " + std::to_string(dim));
    }
    for (int i = 0; i < block_count; ++i) {
      expect_record(in, "element", read + i, count, "$Elements");
      if (type != kTetrahedronType) continue;
      in.expect_exactly(5, "tetrahedron (tag n1 n2 n3 n4)");
      in.integer(0, "element tag");
      read_tet_nodes(in, 1, content);
      content.tet_tags.push_back(entity);
      content.tet_block_lines.push_back(block_line);
    }
    read += block_count;
  }
  if (read != count) {
    in.fail_at(header_line, "bad count: $Elements declares " + std::to_string(count) +
                                " elements, its blocks hold " + std::to_string(read));
  }
  expect_end(in, "$Elements", std::to_string(blocks) + " element blocks (the declared count)");
}

void read_format(MeshTextReader& in, MshContent& content) {
  in.expect_line("$MeshFormat");
  if (in.token(0) != "$MeshFormat") {
    in.fail("not a gmsh mesh: expected $MeshFormat, found '" + std::string(in.token(0)) + "'");
  }
  in.expect_line("the format line (version file-type data-size)");
  in.expect_at_least(3, "format line (version file-type data-size)");
  const std::string_view version = in.token(0);
  if (version == "2.2") {
    content.version = 2;
  } else if (version == "4.1") {
    content.version = 4;
  } else {
    in.fail("unsupported .msh version " + std::string(version) + " (supported: 2.2, 4.1)");
  }
  if (in.integer(1, "file type") != 0) {
    in.fail("binary .msh is not supported (save the mesh as ASCII)");
  }
  expect_end(in, "$MeshFormat", "the format line");
}

TetMesh resolve(const MshContent& content, const MeshTextReader& in) {
  std::unordered_map<long long, int> node_index;
  node_index.reserve(content.node_tags.size());
  for (std::size_t i = 0; i < content.node_tags.size(); ++i) {
    if (!node_index.emplace(content.node_tags[i], static_cast<int>(i)).second) {
      in.fail_at(content.node_lines[i],
                 "duplicate node tag " + std::to_string(content.node_tags[i]));
    }
  }
  const auto num_tets = static_cast<Eigen::Index>(content.tet_nodes.size());
  if (num_tets == 0) in.fail_at(in.line_number(), "no tetrahedra (element type 4) in the file");
  Points nodes(static_cast<Eigen::Index>(content.node_positions.size()), 3);
  for (std::size_t i = 0; i < content.node_positions.size(); ++i) {
    nodes.row(static_cast<Eigen::Index>(i)) = content.node_positions[i].transpose();
  }
  Tets tets(num_tets, 4);
  Eigen::VectorXi labels(num_tets);
  for (Eigen::Index t = 0; t < num_tets; ++t) {
    const auto u = static_cast<std::size_t>(t);
    for (int k = 0; k < 4; ++k) {
      const auto found = node_index.find(content.tet_nodes[u][k]);
      if (found == node_index.end()) {
        in.fail_at(content.tet_lines[u],
                   "node tag " + std::to_string(content.tet_nodes[u][k]) + " is not in $Nodes");
      }
      tets(t, k) = found->second;
    }
    long long label = content.tet_tags[u];
    if (content.version == 4) {
      label = 0;
      if (content.has_entities) {
        const auto volume = content.volume_physical_tag.find(content.tet_tags[u]);
        if (volume == content.volume_physical_tag.end()) {
          in.fail_at(
              content.tet_block_lines[u],
              "volume entity " + std::to_string(content.tet_tags[u]) + " is not in $Entities");
        }
        label = volume->second;
      }
    }
    if (label < 0 || label > 2'000'000'000) {
      in.fail_at(content.tet_lines[u], "physical tag " + std::to_string(label) + " out of range");
    }
    labels(t) = static_cast<int>(label);
  }
  return mesh_from_file_data(nodes, std::move(tets), std::move(labels), content.tet_lines,
                             in.name());
}

}  // namespace

TetMesh read_msh_string(std::string_view text, const std::string& name) {
  MeshTextReader in(text, name);
  MshContent content;
  read_format(in, content);
  bool has_nodes = false;
  bool has_elements = false;
  while (in.next_line()) {
    const std::string section(in.token(0));
    if (section.front() != '$') {
      in.fail("expected a section such as $Nodes, found '" + section + "'");
    }
    if (section == "$Nodes") {
      if (has_nodes) in.fail("a second $Nodes section");
      content.version == 2 ? read_nodes_v2(in, content) : read_nodes_v4(in, content);
      has_nodes = true;
    } else if (section == "$Elements") {
      if (has_elements) in.fail("a second $Elements section");
      content.version == 2 ? read_elements_v2(in, content) : read_elements_v4(in, content);
      has_elements = true;
    } else if (section == "$Entities" && content.version == 4) {
      read_entities_v4(in, content);
    } else {
      // A section we do not need: skip to its end marker.
      const std::string end = "$End" + section.substr(1);
      do {
        in.expect_line(end);
      } while (in.token(0) != end);
    }
  }
  if (!has_nodes) in.fail_at(in.line_number(), "truncated file: no $Nodes section");
  if (!has_elements) in.fail_at(in.line_number(), "truncated file: no $Elements section");
  return resolve(content, in);
}

TetMesh read_msh(const std::filesystem::path& path) {
  return read_msh_string(read_mesh_text(path.string()), path.string());
}

}  // namespace incise::sim
