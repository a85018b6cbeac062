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
#include <type_traits>
#include <vector>

namespace omesh::cgal
{
/// Whether a queue element can tell it was destroyed after it was queued (CGAL::CC_safe_handle).
template <class E, class = void>
struct HasZombies : std::false_type
{
};
template <class E>
struct HasZombies<E, std::void_t<decltype(std::declval<const E&>().is_zombie())>> : std::true_type
{
};

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
    if constexpr (HasZombies<Element>::value)
      if (heap_.size() == heap_.capacity() && !heap_.empty())
        dropZombies();
    heap_.push_back(Entry{ v, next_++ });
    std::push_heap(heap_.begin(), heap_.end(), after);
  }
  Top begin() const { return Top(&heap_.front().value); }
  /// Removes the first element (the only one Filtered_multimap_container erases).
  void erase(const Top&)
  {
    std::pop_heap(heap_.begin(), heap_.end(), after);
    heap_.pop_back();
    if (heap_.size() < heap_.capacity() / 2 && heap_.capacity() > kShrinkAbove)
      shrink();
  }
  bool empty() const { return heap_.empty(); }
  size_type size() const { return heap_.size(); }
  void clear() { heap_.clear(); }
  std::size_t capacity() const { return heap_.capacity(); }
  /// How many elements it found destroyed and dropped before their turn.
  std::size_t dropped() const { return dropped_; }

private:
  struct Entry
  {
    value_type value;
    std::uint64_t sequence; ///< insertion number: the tie-break among equal qualities
  };
  /// Whether a comes out after b (std::push_heap keeps the element no other comes after on top).
  /// A function object, not a function: the heap algorithms inline it (through a function
  /// pointer every comparison was a call).
  struct After
  {
    bool operator()(const Entry& a, const Entry& b) const
    {
      if (b.value.first < a.value.first)
        return true;
      if (a.value.first < b.value.first)
        return false;
      return a.sequence > b.sequence;
    }
  };
  static constexpr After after{};

  /// Before the array would grow: the cells destroyed since they were queued go, as the container
  /// would skip them when they came up; the order of the others is unchanged (a total order:
  /// qualities, then insertion numbers). Grows by a quarter (not the vector's doubling: the queue
  /// is largest near the triangulation's peak) only if that freed less than half; a pass reads
  /// each entry's cell, about five per insertion at most.
  void dropZombies()
  {
    const std::size_t capacity = heap_.capacity();
    const auto end = std::remove_if(heap_.begin(), heap_.end(), [](const Entry& e) { return e.value.second.is_zombie(); });
    dropped_ += static_cast<std::size_t>(heap_.end() - end);
    heap_.erase(end, heap_.end());
    std::make_heap(heap_.begin(), heap_.end(), after);
    if (heap_.size() > capacity / 2)
      heap_.reserve(capacity + capacity / 4);
  }

  /// The array down to a quarter above its length once it is less than half full: the queue drains
  /// while the triangulation grows, and a capacity kept from its largest moment would be alive at
  /// the triangulation's peak.
  void shrink()
  {
    std::vector<Entry> smaller;
    smaller.reserve(heap_.size() + heap_.size() / 4);
    smaller.assign(heap_.begin(), heap_.end());
    heap_.swap(smaller);
  }
  static constexpr std::size_t kShrinkAbove = 1 << 16;

  std::vector<Entry> heap_;
  std::uint64_t next_ = 0;
  std::size_t dropped_ = 0;
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
