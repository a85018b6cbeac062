// SPDX-License-Identifier: GPL-3.0-or-later
// The cell level's refinement queue (CellRefinementQueue.h) pops in the order of the std::multimap
// it replaces: the smallest quality first, equal qualities in the order they came. That order is
// what keeps the mesher's meshes the same.
#include "CellRefinementQueue.h"

#include <gtest/gtest.h>

#include <map>
#include <random>
#include <utility>
#include <vector>

namespace
{
using Quality = std::pair<int, double>;
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
