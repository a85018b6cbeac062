// SPDX-License-Identifier: GPL-3.0-or-later
// The cell level's refinement queue (CellRefinementQueue.h) pops in the order of the std::multimap
// it replaces: the smallest quality first, equal qualities in the order they came. That order is
// what keeps the mesher's meshes the same.
#include "CellRefinementQueue.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <map>
#include <random>
#include <utility>
#include <vector>

namespace
{
using Quality = std::pair<int, double>;

/// A queued element that can be destroyed after it was queued, as CGAL's safe cell handles.
struct Mortal
{
  int id;
  const std::vector<bool>* dead;
  bool is_zombie() const { return (*dead)[static_cast<std::size_t>(id)]; }
};
}

TEST(CellRefinementQueue, PopsInTheMultimapsOrderWithTiesAndInterleavedInsertions)
{
  std::mt19937 random(5);
  std::uniform_int_distribution<int> criterion(0, 2), value(0, 7), action(0, 3);
  std::multimap<Quality, int> reference;
  omesh::cgal::SequencedHeap<Quality, int> heap;
  int next = 0;
  std::vector<int> fromReference, fromHeap;
  for (int step = 0; step < 20000; ++step)
  {
    if (action(random) != 0 || reference.empty())
    {
      // few distinct qualities: many ties, which the insertion order must break
      const Quality q{ criterion(random), 0.125 * value(random) };
      reference.insert({ q, next });
      heap.insert({ q, next });
      ++next;
    }
    else
    {
      ASSERT_EQ(heap.size(), reference.size());
      EXPECT_EQ(heap.begin()->first, reference.begin()->first);
      fromReference.push_back(reference.begin()->second);
      fromHeap.push_back((*heap.begin()).second);
      reference.erase(reference.begin());
      heap.erase(heap.begin());
    }
  }
  while (!reference.empty())
  {
    fromReference.push_back(reference.begin()->second);
    fromHeap.push_back(heap.begin()->second);
    reference.erase(reference.begin());
    heap.erase(heap.begin());
  }
  EXPECT_TRUE(heap.empty());
  EXPECT_GT(fromReference.size(), 10000u);
  EXPECT_EQ(fromHeap, fromReference);
  heap.insert({ { 0, 1.0 }, 1 });
  heap.clear();
  EXPECT_EQ(heap.size(), 0u);
}

TEST(CellRefinementQueue, DropsDestroyedElementsBeforeGrowingAndKeepsTheOrderOfTheOthers)
{
  // As in the refinement: most queued cells are destroyed by later insertions before their turn.
  constexpr int n = 400000;
  std::mt19937 random(11);
  std::uniform_int_distribution<int> criterion(0, 2), value(0, 7);
  std::vector<bool> dead(n, false);
  std::multimap<Quality, int> reference;
  omesh::cgal::SequencedHeap<Quality, Mortal> heap;
  for (int id = 0; id < n; ++id)
  {
    const Quality q{ criterion(random), 0.125 * value(random) };
    reference.insert({ q, id });
    heap.insert({ q, Mortal{ id, &dead } });
    if (id % 4 != 0)
      dead[static_cast<std::size_t>(id)] = true; // three of four die
  }
  EXPECT_GT(heap.dropped(), static_cast<std::size_t>(n / 2));
  EXPECT_LT(heap.capacity(), static_cast<std::size_t>(n / 2)) << "the array grew for elements already destroyed";
  EXPECT_GE(heap.size(), static_cast<std::size_t>(n / 4));

  // popped as Filtered_multimap_container pops (destroyed ones skipped): the multimap's order
  std::vector<int> fromReference, fromHeap;
  for (const auto& [q, id] : reference)
    if (!dead[static_cast<std::size_t>(id)])
      fromReference.push_back(id);
  std::size_t smallestCapacity = heap.capacity();
  while (!heap.empty())
  {
    if (!heap.begin()->second.is_zombie())
      fromHeap.push_back(heap.begin()->second.id);
    heap.erase(heap.begin());
    smallestCapacity = std::min(smallestCapacity, heap.capacity());
  }
  EXPECT_EQ(fromHeap, fromReference);
  EXPECT_LT(smallestCapacity, static_cast<std::size_t>(1) << 17) << "the array kept its largest capacity while it drained";
}
