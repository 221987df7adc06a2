// A vector shared by its copies until one of them changes (copy on
// write). A job's copy of the caller's scene, the flattened Scene's copy and a relight's
// description then hold one storage, and a relight knows its geometry is unchanged by
// comparing pointers instead of every vertex (the add-on's live mode relights the same core
// scene with new lights only). Reading never copies; any non-const access detaches first, so
// a copy never sees another's change. Keep no reference from a non-const access across a
// copy of the description: it would still point into the storage the copy shares.
#pragma once

#include <cstddef>
#include <initializer_list>
#include <memory>
#include <utility>
#include <vector>

namespace bakegi {

template <typename T>
class SharedVector {
 public:
  using value_type = T;
  using iterator = typename std::vector<T>::iterator;
  using const_iterator = typename std::vector<T>::const_iterator;

  SharedVector() : items_(std::make_shared<std::vector<T>>()) {}
  SharedVector(std::initializer_list<T> items)
      : items_(std::make_shared<std::vector<T>>(items)) {}

  size_t size() const { return items_->size(); }
  bool empty() const { return items_->empty(); }
  const T& operator[](size_t i) const { return (*items_)[i]; }
  const T& at(size_t i) const { return items_->at(i); }
  const T& back() const { return items_->back(); }
  const_iterator begin() const { return items_->cbegin(); }
  const_iterator end() const { return items_->cend(); }
  const std::vector<T>& items() const { return *items_; }

  // Non-const access: detaches from the copies first.
  T& operator[](size_t i) { return own()[i]; }
  T& back() { return own().back(); }
  iterator begin() { return own().begin(); }
  iterator end() { return own().end(); }
  void push_back(T mesh) { own().push_back(std::move(mesh)); }
  void resize(size_t count) { own().resize(count); }
  void reserve(size_t count) { own().reserve(count); }

  // Whether this and `other` hold one storage (then they are equal without a look inside).
  bool shares_storage_with(const SharedVector& other) const { return items_ == other.items_; }
  bool operator==(const SharedVector& other) const {
    return items_ == other.items_ || *items_ == *other.items_;
  }

 private:
  std::vector<T>& own() {
    if (items_.use_count() > 1) items_ = std::make_shared<std::vector<T>>(*items_);
    return *items_;
  }

  std::shared_ptr<std::vector<T>> items_;
};

}  // namespace bakegi
