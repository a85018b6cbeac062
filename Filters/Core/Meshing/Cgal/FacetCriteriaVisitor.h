// SPDX-License-Identifier: GPL-3.0-or-later
// PRIVATE (includes CGAL): the visitor of the mesher's facet criteria (MesherCriteria3.h).
#pragma once

#include <CGAL/Mesh_3/mesh_standard_criteria.h>
#include <CGAL/enum.h>

namespace omesh::cgal
{
/// Asks each facet criterion in turn, skipping them all on a facet of three protecting balls that
/// meet (as CGAL's Facet_criterion_visitor_with_features skips any criterion but its own size,
/// angle and curvature ones, which the mesher does not add). CGAL's tells a weighted vertex with a
/// filtered predicate, compare_weighted_squared_radius_3(p, 0) == SMALLER, i.e. -weight < 0: the
/// same as weight > 0 in doubles, without the interval arithmetic (3 predicates a facet).
template <class Tr>
class FacetCriteriaVisitor : public CGAL::Mesh_3::Criterion_visitor<Tr, typename Tr::Facet>
{
  using Base = CGAL::Mesh_3::Criterion_visitor<Tr, typename Tr::Facet>;

public:
  using Criterion = CGAL::Mesh_3::Abstract_criterion<Tr, FacetCriteriaVisitor>;
  using Facet_quality = typename Base::Quality;
  using Is_facet_bad = typename Base::Is_bad;

  FacetCriteriaVisitor(const Tr& tr, const typename Tr::Facet& f)
    : Base(tr, f)
  {
    const auto& p1 = tr.point(f.first, (f.second + 1) & 3);
    const auto& p2 = tr.point(f.first, (f.second + 2) & 3);
    const auto& p3 = tr.point(f.first, (f.second + 3) & 3);
    if (p1.weight() > 0 && p2.weight() > 0 && p3.weight() > 0)
      ballsMeet_ = tr.geom_traits().compare_weighted_squared_radius_3_object()(
                     p1, p2, p3, typename Tr::Geom_traits::FT(0)) != CGAL::LARGER;
  }

  void visit(const Criterion& criterion)
  {
    if (ballsMeet_)
    {
      Base::increment_counter();
      return;
    }
    Base::do_visit(criterion);
  }

private:
  bool ballsMeet_ = false;
};
}
