#include "sim/mesh/box_mesher.h"

#include <array>
#include <stdexcept>
#include <utility>

namespace incise::sim {
namespace {

// A cell corner as a bit mask: bit 0 = +x, bit 1 = +y, bit 2 = +z.
using CellTet = std::array<int, 4>;
using CellSplit = std::array<CellTet, 5>;

int parity(int corner) {
  return ((corner & 1) + ((corner >> 1) & 1) + ((corner >> 2) & 1)) % 2;
}

Vec3 corner_position(int corner) {
  return Vec3(corner & 1 ? 1.0 : 0.0, corner & 2 ? 1.0 : 0.0, corner & 4 ? 1.0 : 0.0);
}

// The 5-tet split of the unit cell whose central tet uses the corners of the given local parity,
// each tet ordered to be positively oriented.
CellSplit five_tet_split(int central_parity) {
  CellSplit split{};
  int n = 0;
  CellTet central{};
  int m = 0;
  for (int corner = 0; corner < 8; ++corner) {
    if (parity(corner) == central_parity) {
      central[static_cast<std::size_t>(m++)] = corner;
    } else {
      split[static_cast<std::size_t>(n++)] = {corner, corner ^ 1, corner ^ 2, corner ^ 4};
    }
  }
  split[4] = central;
  for (CellTet& tet : split) {
    if (signed_volume(corner_position(tet[0]), corner_position(tet[1]), corner_position(tet[2]),
                      corner_position(tet[3])) < 0) {
      std::swap(tet[2], tet[3]);
    }
  }
  return split;
}

}  // namespace

TetMesh make_box_mesh(const Vec3& size, const Vec3i& cells) {
  if (!size.allFinite() || !(size.array() > 0).all()) {
    throw std::invalid_argument("box size must be positive and finite");
  }
  if ((cells.array() < 1).any()) throw std::invalid_argument("box cell counts must be >= 1");
  const Vec3i counts = cells.array() + 1;
  const auto node = [&counts](int i, int j, int k) {
    return i + counts.x() * (j + counts.y() * k);
  };
  // The last grid line is placed on size itself: size * n / n can miss it by an ulp.
  const auto coordinate = [&size, &cells](int axis, int i) {
    return i == cells(axis) ? size(axis) : size(axis) * i / cells(axis);
  };

  Points rest(static_cast<Eigen::Index>(counts.prod()), 3);
  for (int k = 0; k < counts.z(); ++k) {
    for (int j = 0; j < counts.y(); ++j) {
      for (int i = 0; i < counts.x(); ++i) {
        rest.row(node(i, j, k)) << coordinate(0, i), coordinate(1, j), coordinate(2, k);
      }
    }
  }

  // A cell at grid parity p puts its central tet on its corners of local parity p, which are the
  // nodes of even global parity.
  const std::array<CellSplit, 2> splits = {five_tet_split(0), five_tet_split(1)};
  Tets tets(static_cast<Eigen::Index>(cells.prod()) * 5, 4);
  Eigen::Index t = 0;
  for (int k = 0; k < cells.z(); ++k) {
    for (int j = 0; j < cells.y(); ++j) {
      for (int i = 0; i < cells.x(); ++i) {
        for (const CellTet& tet : splits[static_cast<std::size_t>((i + j + k) % 2)]) {
          for (int c = 0; c < 4; ++c) {
            const int corner = tet[static_cast<std::size_t>(c)];
            tets(t, c) = node(i + (corner & 1), j + ((corner >> 1) & 1), k + ((corner >> 2) & 1));
          }
          ++t;
        }
      }
    }
  }
  return make_tet_mesh(std::move(rest), std::move(tets));
}

}  // namespace incise::sim
