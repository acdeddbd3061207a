#pragma once

// One small mesh written by hand in each format the readers take, with the mesh they must give.
// Two tets over 5 used nodes; node tags are not contiguous, there is an unused geometry node
// (tag 99), skipped non-tet elements, a tet with physical tag 7 and one without, and the second
// tet is written negatively oriented (signed volume -1/3).

#include <string>

#include "sim/core/types.h"

namespace incise::sim::test {

// Line numbers matter: the error tests point at them.
inline const std::string kMsh22 =  // line
    "$MeshFormat\n"                // 1
    "2.2 0 8\n"                    // 2
    "$EndMeshFormat\n"             // 3
    "$PhysicalNames\n"             // 4
    "1\n"                          // 5
    "3 7 \"liver\"\n"              // 6
    "$EndPhysicalNames\n"          // 7
    "$Nodes\n"                     // 8
    "6\n"                          // 9
    "10 0 0 0\n"                   // 10
    "20 1 0 0\n"                   // 11
    "30 0 1 0\n"                   // 12
    "40 0 0 1\n"                   // 13
    "50 1 1 1\n"                   // 14
    "99 5 5 5\n"                   // 15
    "$EndNodes\n"                  // 16
    "$Elements\n"                  // 17
    "4\n"                          // 18
    "1 15 2 0 1 10\n"              // 19  a point element
    "2 2 2 0 1 10 20 30\n"         // 20  a triangle
    "3 4 2 7 1 10 20 30 40\n"      // 21  tet, physical tag 7
    "4 4 0 20 40 30 50\n"          // 22  tet without tags, negatively oriented
    "$EndElements\n";              // 23

inline const std::string kMsh41 =
    "$MeshFormat\n"          // 1
    "4.1 0 8\n"              // 2
    "$EndMeshFormat\n"       // 3
    "$Entities\n"            // 4
    "1 0 1 2\n"              // 5  1 point, 0 curves, 1 surface, 2 volumes
    "5 5 5 5 0\n"            // 6  point 5
    "1 0 0 0 1 1 1 0 0\n"    // 7  surface 1
    "1 0 0 0 1 1 1 1 7 0\n"  // 8  volume 1, physical tag 7
    "2 0 0 0 1 1 1 0 0\n"    // 9  volume 2, no physical tag
    "$EndEntities\n"         // 10
    "$Nodes\n"               // 11
    "3 6 10 99\n"            // 12
    "0 5 0 1\n"              // 13 block on point 5
    "99\n"                   // 14
    "5 5 5\n"                // 15
    "2 1 1 2\n"              // 16 parametric block on surface 1: x y z u v
    "10\n"                   // 17
    "20\n"                   // 18
    "0 0 0 0 0\n"            // 19
    "1 0 0 1 0\n"            // 20
    "3 1 0 3\n"              // 21 block in volume 1
    "30\n"                   // 22
    "40\n"                   // 23
    "50\n"                   // 24
    "0 1 0\n"                // 25
    "0 0 1\n"                // 26
    "1 1 1\n"                // 27
    "$EndNodes\n"            // 28
    "$Elements\n"            // 29
    "3 3 1 4\n"              // 30
    "2 1 2 1\n"              // 31 triangles on surface 1
    "2 10 20 30\n"           // 32
    "3 1 4 1\n"              // 33 tets in volume 1
    "3 10 20 30 40\n"        // 34
    "3 2 4 1\n"              // 35 tets in volume 2
    "4 20 40 30 50\n"        // 36
    "$EndElements\n";        // 37

// TetGen, numbered from 1, with comments and a blank line; the ele attribute is the label.
inline const std::string kNode =
    "# sample mesh\n"        // 1
    "5 3 0 0\n"              // 2
    "1 0 0 0\n"              // 3
    "2 1 0 0   # comment\n"  // 4
    "3 0 1 0\n"              // 5
    "4 0 0 1\n"              // 6
    "\n"                     // 7
    "5 1 1 1\n";             // 8
inline const std::string kEle =
    "2 4 1\n"         // 1
    "1 1 2 3 4 7\n"   // 2
    "2 2 4 3 5 0\n";  // 3

// What every sample reads as: nodes in file order without the unused one, the second tet with
// its last two nodes swapped to positive orientation.
inline Points expected_nodes() {
  Points nodes(5, 3);
  nodes << 0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1, 1, 1, 1;
  return nodes;
}
inline Tets expected_tets() {
  Tets tets(2, 4);
  tets << 0, 1, 2, 3, 1, 3, 4, 2;
  return tets;
}
inline Eigen::VectorXi expected_labels() {
  return (Eigen::VectorXi(2) << 7, 0).finished();
}

}  // namespace incise::sim::test
