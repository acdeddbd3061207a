#include "sim/remesh/predicates.h"

#include <algorithm>
#include <array>

// The one place in sim/remesh/ that includes CGAL (STYLE.md).
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>

namespace incise::sim::remesh {
namespace {

using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;
using Point = Kernel::Point_3;

Point point(const Vec3& p) {
  return Point(p.x(), p.y(), p.z());
}

int sign_of(CGAL::Sign s) {
  return s == CGAL::POSITIVE ? 1 : (s == CGAL::NEGATIVE ? -1 : 0);
}

}  // namespace

int orientation(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d) {
  return sign_of(CGAL::orientation(point(a), point(b), point(c), point(d)));
}

bool collinear(const Vec3& a, const Vec3& b, const Vec3& c) {
  return CGAL::collinear(point(a), point(b), point(c));
}

int side_of_sphere(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d, const Vec3& e) {
  // CGAL: for a positively oriented (a, b, c, d) the positive side is the bounded interior.
  return sign_of(CGAL::side_of_oriented_sphere(point(a), point(b), point(c), point(d), point(e)));
}

int side_of_sphere_perturbed(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d,
                             const Vec3& e, int key_a, int key_b, int key_c, int key_d, int key_e) {
  const int exact = side_of_sphere(a, b, c, d, e);
  if (exact != 0) return exact;
  // The in-sphere value is the 5 x 5 determinant D(a, b, c, d, e) over rows (p, |p|^2, 1),
  // alternating in its five arguments. Raising the lifted height of e moves e outside, so
  // dD/dh_e = -k orient(a, b, c, d) with k > 0; swapping e with the point in slot j (which
  // flips the sign of D) gives dD/dh_j = +k orient(the tet with slot j replaced by e). With
  // the perturbations ordered by key, the sign of the perturbed D is that of the first
  // non-zero derivative, taken in decreasing key order.
  std::array<const Vec3*, 5> p = {&a, &b, &c, &d, &e};
  std::array<int, 5> keys = {key_a, key_b, key_c, key_d, key_e};
  std::array<int, 5> slots = {0, 1, 2, 3, 4};
  std::sort(slots.begin(), slots.end(), [&](int i, int j) { return keys[i] > keys[j]; });
  for (int slot : slots) {
    int s = 0;
    if (slot == 4) {
      s = -orientation(a, b, c, d);
    } else {
      std::array<const Vec3*, 4> tet = {&a, &b, &c, &d};
      tet[slot] = p[4];
      s = orientation(*tet[0], *tet[1], *tet[2], *tet[3]);
    }
    if (s != 0) return s;
  }
  return 0;  // unreachable for a positively oriented (a, b, c, d): the e slot is non-zero
}

}  // namespace incise::sim::remesh
