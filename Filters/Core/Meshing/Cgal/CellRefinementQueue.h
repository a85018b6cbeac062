// SPDX-License-Identifier: GPL-3.0-or-later
// Private to the mesher (includes CGAL): the sequential cell level's refinement queue as a binary
// heap instead of CGAL's std::multimap. Included by MeshTriangulation3.h, so that every translation
// unit that instantiates the mesher's Mesh_3 levels sees it before the first instantiation.
#pragma once

#include <CGAL/CC_safe_handle.h>
#include <CGAL/Compact_container.h>
#include <CGAL/Meshes/Filtered_multimap_container.h>
#include <CGAL/tags.h>

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <utility>
#include <vector>

namespace omesh::cgal
{
/// A priority queue with the interface Filtered_multimap_container asks of its std::multimap
/// (insert, begin, erase of the first element, empty, size, clear) and the same order: the
/// smallest quality first, equal qualities in the order they came (a multimap inserts an equal
/// key after the others). So the cells are refined in the same order and the mesh is the same;
/// but an insertion costs a push into a contiguous array, not an allocated tree node and a walk of
/// ~20 dependent loads (with CGAL_MESH_3_USE_LAZY_SORTED_REFINEMENT_QUEUE the multimap's
/// insertions cost a fifth of a label map's refinement).
template <typename Quality, typename Element>
class SequencedHeap
{
public:
  using value_type = std::pair<Quality, Element>;
  using size_type = std::size_t;

  /// What begin() gives: the first element, read through -> and *.
  class Top
  {
  public:
    explicit Top(const value_type* v)
      : v_(v)
    {
    }
    const value_type* operator->() const { return v_; }
    const value_type& operator*() const { return *v_; }

  private:
    const value_type* v_;
  };

  void insert(const value_type& v)
  {
    heap_.push_back(Entry{ v, next_++ });
    std::push_heap(heap_.begin(), heap_.end(), after);
  }
  Top begin() const { return Top(&heap_.front().value); }
  /// Removes the first element (the only one Filtered_multimap_container erases).
  void erase(const Top&)
  {
    std::pop_heap(heap_.begin(), heap_.end(), after);
    heap_.pop_back();
  }
  bool empty() const { return heap_.empty(); }
  size_type size() const { return heap_.size(); }
  void clear() { heap_.clear(); }

private:
  struct Entry
  {
    value_type value;
    std::uint64_t sequence; ///< insertion number: the tie-break among equal qualities
  };
  /// Whether a comes out after b (std::push_heap keeps the element no other comes after on top).
  static bool after(const Entry& a, const Entry& b)
  {
    if (b.value.first < a.value.first)
      return true;
    if (a.value.first < b.value.first)
      return false;
    return a.sequence > b.sequence;
  }

  std::vector<Entry> heap_;
  std::uint64_t next_ = 0;
};
}

namespace CGAL::Meshes
{
/// The sequential base of CGAL's filtered multimap container for elements held by safe handles
/// (Refine_cells_3's cells; the facet level's elements are tuples and keep CGAL's multimap): the
/// primary template's members, with SequencedHeap as its Map.
template <typename Handle, typename Quality>
class Filtered_multimap_container_base<CGAL::CC_safe_handle<Handle>, Quality, CGAL::Sequential_tag>
{
public:
  using Element = CGAL::CC_safe_handle<Handle>;
  typedef omesh::cgal::SequencedHeap<Quality, Element> Map;
  typedef typename Map::size_type size_type;
  typedef typename Map::value_type value_type;

  void add_to_TLS_lists_impl(bool) {}
  Element get_next_local_element_impl() { return Element(); }
  value_type get_next_local_raw_element_impl() { return value_type(); }
  void pop_next_local_element_impl() {}

protected:
  Filtered_multimap_container_base() {}
  Filtered_multimap_container_base(bool) {}

  template <typename Container>
  void splice_local_lists_impl(Container&)
  {
  }

  template <typename Predicate>
  bool no_longer_local_element_to_refine_impl(const Predicate&)
  {
    return true;
  }

  template <typename Container>
  void insert_raw_element(const value_type& re, Container& container)
  {
    container.insert(re);
  }
};
}
