// A bounded multi-producer queue for the service's stages. Private.
#ifndef GROUNDLINE_SERVICE_SRC_SERVICE_QUEUES_H_
#define GROUNDLINE_SERVICE_SRC_SERVICE_QUEUES_H_

#include <chrono>
#include <condition_variable>
#include <deque>
#include <mutex>
#include <optional>

namespace groundline::service::internal {

template <typename T>
class BoundedQueue {
 public:
  explicit BoundedQueue(std::size_t capacity) : capacity_(capacity) {}

  // Appends; when full, drops the oldest entry and returns it.
  std::optional<T> Push(T value) {
    std::optional<T> dropped;
    {
      std::lock_guard<std::mutex> lock(mutex_);
      if (items_.size() >= capacity_) {
        dropped = std::move(items_.front());
        items_.pop_front();
      }
      items_.push_back(std::move(value));
    }
    ready_.notify_one();
    return dropped;
  }
  // Appends, waiting while the queue is full (backpressure for an input that
  // can wait, such as a replay as fast as possible).
  void PushWait(T value) {
    {
      std::unique_lock<std::mutex> lock(mutex_);
      space_.wait(lock, [this] { return items_.size() < capacity_ || closed_; });
      items_.push_back(std::move(value));
    }
    ready_.notify_one();
  }
  // The oldest entry, waiting up to `timeout`; nullopt on time-out or when
  // closed and empty.
  std::optional<T> Pop(std::chrono::milliseconds timeout) {
    std::unique_lock<std::mutex> lock(mutex_);
    ready_.wait_for(lock, timeout, [this] { return !items_.empty() || closed_; });
    if (items_.empty()) return std::nullopt;
    T value = std::move(items_.front());
    items_.pop_front();
    lock.unlock();
    space_.notify_one();
    return value;
  }
  void Close() {
    {
      std::lock_guard<std::mutex> lock(mutex_);
      closed_ = true;
    }
    ready_.notify_all();
    space_.notify_all();
  }
  bool closed_and_empty() const {
    std::lock_guard<std::mutex> lock(mutex_);
    return closed_ && items_.empty();
  }

 private:
  const std::size_t capacity_;
  mutable std::mutex mutex_;
  std::condition_variable ready_;
  std::condition_variable space_;
  std::deque<T> items_;
  bool closed_ = false;
};

}  // namespace groundline::service::internal

#endif  // GROUNDLINE_SERVICE_SRC_SERVICE_QUEUES_H_
