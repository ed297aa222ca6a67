// The id table of run-time inputs (docs/SPEC.md "Run-time inputs", eqs
// 118-119): names bodies by BodyId {slot, generation} across creations and
// removals. Per body index its slot; per slot its generation and the body
// it holds (-1: free). A creation takes the lowest free slot (a new one when
// none is free); a removal raises its slot's generation, so that the old id
// goes stale, and moves the bodies after it down one index. Shared by
// World<T> and the GPU engine, so that both give the same ids.
#pragma once
#include <cstddef>
#include <cstdint>
#include <limits>
#include <stdexcept>
#include <string>
#include <vector>

#include "lockstep/input.hpp"

namespace lockstep {

class BodyIds {
 public:
  // Body i in slot i, generation 0.
  void reset(std::size_t bodies) {
    slot_of_.resize(bodies);
    index_of_slot_.resize(bodies);
    for (std::size_t i = 0; i < bodies; ++i) {
      slot_of_[i] = static_cast<std::uint32_t>(i);
      index_of_slot_[i] = static_cast<int>(i);
    }
    generation_.assign(bodies, 0u);
  }

  std::size_t bodies() const { return slot_of_.size(); }
  std::size_t slots() const { return generation_.size(); }
  std::uint32_t slot_of(std::size_t index) const { return slot_of_[index]; }
  std::uint32_t generation(std::size_t slot) const { return generation_[slot]; }
  // Whether the table is reset(bodies()): no body was ever removed.
  bool identity() const {
    if (generation_.size() != slot_of_.size()) return false;
    for (std::size_t i = 0; i < slot_of_.size(); ++i)
      if (slot_of_[i] != i || generation_[i] != 0) return false;
    return true;
  }

  bool contains(BodyId id) const {
    return id.slot < generation_.size() && index_of_slot_[id.slot] >= 0 && generation_[id.slot] == id.generation;
  }

  // The index of the live body `id`; throws std::invalid_argument naming the
  // id, why it names no body and what to do, prefixed by `what`.
  std::size_t require(BodyId id, const std::string& what) const {
    const std::string name = what + ": body (slot " + std::to_string(id.slot) + ", generation " +
                             std::to_string(id.generation) + ")";
    if (id.slot >= generation_.size())
      throw std::invalid_argument(name + " names no body: the slots are 0.." + std::to_string(generation_.size()) +
                                  " (exclusive); use an id that create_body or id_of returned");
    const int index = index_of_slot_[id.slot];
    if (index >= 0 && generation_[id.slot] == id.generation) return static_cast<std::size_t>(index);
    const std::string now = index < 0 ? "slot " + std::to_string(id.slot) + " is free"
                                      : "slot " + std::to_string(id.slot) + " now holds another body (generation " +
                                            std::to_string(generation_[id.slot]) + ")";
    throw std::invalid_argument(name + " is stale: " +
                                (id.generation < generation_[id.slot] ? "that body was destroyed and " : "") + now +
                                "; drop the input, or use the id of a live body (id_of, contains)");
  }

  BodyId id_of(std::size_t index) const {
    if (index >= slot_of_.size())
      throw std::invalid_argument("id_of: index = " + std::to_string(index) + " is not a body index: there are " +
                                  std::to_string(slot_of_.size()) + " bodies");
    return {slot_of_[index], generation_[slot_of_[index]]};
  }

  // The id the next add() returns: the lowest free slot whose generation can
  // still grow (a slot at generation 2^32 - 1 is retired), else a new slot.
  BodyId next() const {
    for (std::size_t s = 0; s < index_of_slot_.size(); ++s)
      if (index_of_slot_[s] < 0 && generation_[s] != std::numeric_limits<std::uint32_t>::max())
        return {static_cast<std::uint32_t>(s), generation_[s]};
    return {static_cast<std::uint32_t>(index_of_slot_.size()), 0u};
  }

  // A body appended at index bodies(): its id.
  BodyId add() {
    const BodyId id = next();
    if (id.slot == generation_.size()) {
      generation_.push_back(0u);
      index_of_slot_.push_back(-1);
    }
    index_of_slot_[id.slot] = static_cast<int>(slot_of_.size());
    slot_of_.push_back(id.slot);
    return id;
  }

  // Body `index` removed: its id goes stale, the bodies after it move down one.
  void remove(std::size_t index) {
    const std::uint32_t slot = slot_of_[index];
    if (generation_[slot] != std::numeric_limits<std::uint32_t>::max()) ++generation_[slot];  // else retired
    index_of_slot_[slot] = -1;
    for (int& i : index_of_slot_)
      if (i > static_cast<int>(index)) --i;
    slot_of_.erase(slot_of_.begin() + static_cast<std::ptrdiff_t>(index));
  }

  // A table read back (a snapshot): the slots' generations and each body's
  // slot. Returns "" or what is wrong (a slot past the table or used twice).
  std::string assign(std::vector<std::uint32_t> generations, std::vector<std::uint32_t> slot_of_body) {
    std::vector<int> index_of_slot(generations.size(), -1);
    for (std::size_t i = 0; i < slot_of_body.size(); ++i) {
      const std::uint32_t s = slot_of_body[i];
      if (s >= generations.size() || index_of_slot[s] >= 0)
        return "body " + std::to_string(i) + "'s slot " + std::to_string(s) + " is past the " +
               std::to_string(generations.size()) + " slots or holds another body";
      index_of_slot[s] = static_cast<int>(i);
    }
    generation_ = std::move(generations);
    slot_of_ = std::move(slot_of_body);
    index_of_slot_ = std::move(index_of_slot);
    return "";
  }

 private:
  std::vector<std::uint32_t> slot_of_;     // per body index
  std::vector<std::uint32_t> generation_;  // per slot
  std::vector<int> index_of_slot_;         // per slot: the body it holds, -1 free
};

}  // namespace lockstep
