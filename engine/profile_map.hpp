#pragma once
// A map from name to value for the per-step profile (profile.hpp) that allocates only when
// it meets a name for the first time: clear() marks entries absent and keeps them, so a
// step that reports the same names as the steps before it allocates nothing (the step is
// allocation-free after warm-up, issue 7). Reads like the std::map it replaces: sorted
// by name, present entries only, elements std::pair<std::string, V> (do not rename one).
#include <iterator>
#include <list>
#include <stdexcept>
#include <string>
#include <string_view>
#include <utility>

namespace sinew {

template <typename V>
class ProfileMap {
  struct Entry {
    std::pair<std::string, V> item;
    bool present = false;
  };
  using List = std::list<Entry>;

  template <typename Base, typename Item>
  class Iterator {
   public:
    using iterator_category = std::forward_iterator_tag;
    using value_type = std::pair<std::string, V>;
    using difference_type = std::ptrdiff_t;
    using pointer = Item*;
    using reference = Item&;
    Iterator(Base at, Base end) : m_at(at), m_end(end) { skip_absent(); }
    reference operator*() const { return m_at->item; }
    pointer operator->() const { return &m_at->item; }
    Iterator& operator++() {
      ++m_at;
      skip_absent();
      return *this;
    }
    bool operator==(const Iterator& other) const { return m_at == other.m_at; }
    bool operator!=(const Iterator& other) const { return m_at != other.m_at; }

   private:
    void skip_absent() {
      while (m_at != m_end && !m_at->present) ++m_at;
    }
    Base m_at, m_end;
  };

 public:
  using iterator = Iterator<typename List::iterator, std::pair<std::string, V>>;
  using const_iterator = Iterator<typename List::const_iterator, const std::pair<std::string, V>>;

  ProfileMap() = default;
  ProfileMap(std::initializer_list<std::pair<std::string, V>> items) {
    for (const auto& [name, value] : items) (*this)[name] = value;
  }

  // The entry for `name`, value-initialised when it was absent.
  V& operator[](std::string_view name) {
    auto at = m_entries.begin();
    while (at != m_entries.end() && at->item.first < name) ++at;
    if (at == m_entries.end() || at->item.first != name)
      at = m_entries.insert(at, Entry{{std::string(name), V{}}, false});
    if (!at->present) {
      at->item.second = V{};
      at->present = true;
    }
    return at->item.second;
  }
  std::size_t count(std::string_view name) const { return find_entry(name) ? 1 : 0; }
  const V& at(std::string_view name) const {
    if (const Entry* e = find_entry(name)) return e->item.second;
    throw std::out_of_range("ProfileMap::at: no entry " + std::string(name));
  }
  iterator find(std::string_view name) {
    for (auto it = begin(); it != end(); ++it)
      if (it->first == name) return it;
    return end();
  }
  const_iterator find(std::string_view name) const {
    for (auto it = begin(); it != end(); ++it)
      if (it->first == name) return it;
    return end();
  }
  bool empty() const { return begin() == end(); }
  std::size_t size() const { return static_cast<std::size_t>(std::distance(begin(), end())); }
  // Marks every entry absent, keeping its storage.
  void clear() {
    for (Entry& e : m_entries) e.present = false;
  }

  iterator begin() { return {m_entries.begin(), m_entries.end()}; }
  iterator end() { return {m_entries.end(), m_entries.end()}; }
  const_iterator begin() const { return {m_entries.begin(), m_entries.end()}; }
  const_iterator end() const { return {m_entries.end(), m_entries.end()}; }

  bool operator==(const ProfileMap& other) const {
    auto a = begin(), b = other.begin();
    for (; a != end() && b != other.end(); ++a, ++b)
      if (*a != *b) return false;
    return a == end() && b == other.end();
  }

 private:
  const Entry* find_entry(std::string_view name) const {
    for (const Entry& e : m_entries)
      if (e.present && e.item.first == name) return &e;
    return nullptr;
  }
  List m_entries;
};

}  // namespace sinew
