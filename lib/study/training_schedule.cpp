// Step 4's schedule (scene_networks.hpp, train_networks): the sizes on a team of threads, one trainer each,
// the study's critical size at the process's priority and the speculative ones niced.
#include <sys/resource.h>
#include <sys/syscall.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <condition_variable>
#include <cstdio>
#include <exception>
#include <limits>
#include <mutex>
#include <optional>
#include <thread>

#include "study/scene_networks.hpp"
#include "study/study_detail.hpp"
#include "study/training_data.hpp"

namespace contactnn::study {

using detail::Clock;
using detail::fresh_network;
using detail::network_name;
using detail::prepare_training;
using detail::seconds_since;
using detail::snapshot;
using detail::team_size;
using detail::TrainingData;

namespace {

/// Thread priorities of the training: a thread training what the study waits for runs at the process's own
/// nice value, one training ahead of time (a size that may turn out unneeded) kSpeculativeNice above it, so
/// that speculation takes only the cores nothing else wants (on a busy 2-core machine, the smallest Gregory
/// size took 14 s beside an unniced speculative one, 6 s alone). A thread must get its priority back when its
/// work becomes the one waited for, which Linux allows only with privilege or RLIMIT_NICE: where a throwaway
/// thread cannot, no thread changes its priority at all.
constexpr int kSpeculativeNice = 10;

class ThreadPriority {
 public:
  ThreadPriority() {
    errno = 0;
    const int nice = getpriority(PRIO_PROCESS, 0);
    if (errno != 0) return;
    base_ = nice;
    std::thread([&] {
      const auto tid = static_cast<id_t>(syscall(SYS_gettid));
      enabled_ = setpriority(PRIO_PROCESS, tid, std::min(base_ + kSpeculativeNice, 19)) == 0 &&
                 setpriority(PRIO_PROCESS, tid, base_) == 0;
    }).join();
  }
  /// Sets the calling thread's priority (once per change; nothing when disabled).
  void set(bool speculative) const {
    thread_local int current = std::numeric_limits<int>::min();
    const int nice = speculative ? std::min(base_ + kSpeculativeNice, 19) : base_;
    if (!enabled_ || nice == current) return;
    if (setpriority(PRIO_PROCESS, static_cast<id_t>(syscall(SYS_gettid)), nice) == 0) current = nice;
  }

 private:
  int base_ = 0;
  bool enabled_ = false;
};

/// Step 4's schedule (the header comment of train_networks): the sizes on a team of threads, one trainer
/// each.
class TrainingSchedule {
 public:
  TrainingSchedule(const SceneDomain& domain, SurfaceKind surface, const SceneStudyOptions& o,
                   const std::vector<int>& sizes, const StudyLog& log)
      : domain_(domain),
        surface_(surface),
        o_(o),
        log_(log),
        data_(prepare_training(domain.train, o)),
        long_round_(o.long_epochs > o.epochs) {
    mlp::TrainOptions t;
    t.mode = mlp::TrainingMode::kOnline;
    t.learning_rate = o.learning_rate;
    t.momentum = o.momentum;
    // The learning rate is constant, so a trainer set up for long_epochs runs its first `epochs` exactly as
    // one set up for `epochs`: the long round is the same training carried on.
    t.epochs = std::max(o.epochs, o.long_epochs);
    t.patience = 0;
    t.restore_best = true;
    t.seed = o.seed;
    t.threads = 1;
    for (const int h : sizes) {
      auto slot = std::make_unique<Slot>();
      slot->hidden = h;
      slot->network = std::make_unique<mlp::Network<float>>(fresh_network(surface, h, data_, o));
      slot->trainer = std::make_unique<mlp::Trainer<float>>(*slot->network, t, data_.train_x, data_.train_t,
                                                            data_.validation_x, data_.validation_t);
      slots_.push_back(std::move(slot));
    }
  }

  NetworkTraining run() {
    const auto start = Clock::now();
    const int team = std::max(1, std::min(team_size(o_), static_cast<int>(slots_.size())));
    std::vector<std::thread> threads;
    std::exception_ptr failure;
    std::mutex failure_mutex;
    for (int t = 0; t < team; ++t) {
      threads.emplace_back([&] {
        try {
          work();
        } catch (...) {
          const std::lock_guard<std::mutex> lock(failure_mutex);
          if (!failure) failure = std::current_exception();
          const std::lock_guard<std::mutex> state(mutex_);
          finished_ = true;
          changed_.notify_all();
        }
      });
    }
    for (std::thread& t : threads) t.join();
    if (failure) std::rethrow_exception(failure);
    return result(seconds_since(start));
  }

 private:
  struct Slot {
    int hidden = 0;
    std::unique_ptr<mlp::Network<float>> network;
    std::unique_ptr<mlp::Trainer<float>> trainer;
    bool taken = false;       // a thread is training it
    bool round_done = false;  // its `epochs` are done and judged
    bool cancelled = false;   // dropped: a smaller size reached the target first
    std::optional<SceneNetwork> round, long_round;
    double seconds = 0.0;
  };

  double target() const { return o_.margin * o_.target; }

  void say(const std::string& line) const {
    if (log_) log_(line);
  }

  bool round_complete() const {
    return std::all_of(slots_.begin(), slots_.end(),
                       [](const auto& s) { return s->round_done || s->cancelled; });
  }

  /// The size the study waits for: the smallest still in the first round (-1: the round is complete).
  int critical() const {
    for (std::size_t i = 0; i < slots_.size(); ++i) {
      if (!slots_[i]->round_done && !slots_[i]->cancelled) return static_cast<int>(i);
    }
    return -1;
  }

  /// The finished size of the lowest held-out error (-1: none).
  int best_finished(bool free_only) const {
    int best = -1;
    for (std::size_t i = 0; i < slots_.size(); ++i) {
      const Slot& s = *slots_[i];
      if (!s.round_done || (free_only && (s.taken || s.long_round))) continue;
      if (best < 0 ||
          s.round->heldout_error() < slots_[static_cast<std::size_t>(best)]->round->heldout_error()) {
        best = static_cast<int>(i);
      }
    }
    return best;
  }

  void work() {
    std::unique_lock<std::mutex> lock(mutex_);
    while (!finished_) {
      if (next_ < slots_.size()) {  // a size of the first round
        const std::size_t i = next_++;
        slots_[i]->taken = true;
        lock.unlock();
        first_round(i);
        lock.lock();
        continue;
      }
      if (round_complete()) {
        if (reached_ >= 0 || !long_round_) break;
        const auto b = static_cast<std::size_t>(best_finished(false));
        if (slots_[b]->long_round) break;  // carried on to the end ahead of time
        if (slots_[b]->taken) {            // its thread carries it on
          changed_.wait(lock);
          continue;
        }
        slots_[b]->taken = true;
        lock.unlock();
        carry_on(b);
        lock.lock();
        continue;
      }
      // The other threads are still in the first round: carry the best finished size on ahead of time.
      const int ahead = reached_ < 0 && long_round_ ? best_finished(true) : -1;
      if (ahead >= 0) {
        slots_[static_cast<std::size_t>(ahead)]->taken = true;
        lock.unlock();
        carry_on(static_cast<std::size_t>(ahead));
        lock.lock();
        continue;
      }
      changed_.wait(lock);
    }
    finished_ = true;
    changed_.notify_all();
  }

  /// The first `epochs` of size i, then its held-out error; stops early when a smaller size reaches the
  /// target.
  void first_round(std::size_t i) {
    Slot& s = *slots_[i];
    const auto start = Clock::now();
    while (s.trainer->state().epoch < o_.epochs) {
      {
        const std::lock_guard<std::mutex> lock(mutex_);
        if (finished_ || (reached_ >= 0 && static_cast<std::size_t>(reached_) < i)) {
          s.cancelled = true;
          s.taken = false;
          changed_.notify_all();
          return;
        }
        priority_.set(critical() != static_cast<int>(i));
      }
      (void)s.trainer->train_epoch();
    }
    s.seconds += seconds_since(start);
    SceneNetwork n =
        snapshot(*s.network, s.trainer->state(), network_name(surface_, s.hidden, o_.second_layer), s.hidden,
                 data_, domain_.heldout_set, o_);
    n.seconds = s.seconds;
    const std::lock_guard<std::mutex> lock(mutex_);
    char line[200];
    std::snprintf(line, sizeof line,
                  "%s, %d epochs: held-out mean |error| %.5f / %.5f (target %g, margin %g), %.1f s",
                  n.name.c_str(), n.epochs, n.heldout_mean_abs[0], n.heldout_mean_abs[1], o_.target,
                  o_.margin, n.seconds);
    say(line);
    if (n.heldout_error() <= target() && (reached_ < 0 || static_cast<int>(i) < reached_))
      reached_ = static_cast<int>(i);
    s.round = std::move(n);
    s.round_done = true;
    s.taken = false;
    changed_.notify_all();
  }

  /// Size i trained on towards long_epochs; stops when it is no longer the best (or a size reached the
  /// target).
  void carry_on(std::size_t i) {
    Slot& s = *slots_[i];
    const auto start = Clock::now();
    while (s.trainer->state().epoch < o_.long_epochs) {
      {
        const std::lock_guard<std::mutex> lock(mutex_);
        const bool overtaken = round_complete() && best_finished(false) != static_cast<int>(i);
        if (finished_ || reached_ >= 0 || overtaken) {
          s.seconds += seconds_since(start);
          s.taken = false;
          changed_.notify_all();
          return;
        }
        priority_.set(!round_complete());
      }
      (void)s.trainer->train_epoch();
    }
    s.seconds += seconds_since(start);
    SceneNetwork n =
        snapshot(*s.network, s.trainer->state(), network_name(surface_, s.hidden, o_.second_layer) + "-long",
                 s.hidden, data_, domain_.heldout_set, o_);
    n.seconds = s.seconds;
    const std::lock_guard<std::mutex> lock(mutex_);
    char line[200];
    std::snprintf(line, sizeof line, "%s, %d epochs: held-out mean |error| %.5f / %.5f, %.1f s in all",
                  n.name.c_str(), n.epochs, n.heldout_mean_abs[0], n.heldout_mean_abs[1], n.seconds);
    say(line);
    s.long_round = std::move(n);
    s.taken = false;
    changed_.notify_all();
  }

  NetworkTraining result(double seconds) {
    NetworkTraining out;
    out.seconds = seconds;
    int reached_index = -1, long_index = -1;
    for (std::size_t i = 0; i < slots_.size(); ++i) {
      if (!slots_[i]->round) continue;
      if (static_cast<int>(i) == reached_) reached_index = static_cast<int>(out.tried.size());
      out.tried.push_back(*slots_[i]->round);
    }
    const int best = reached_ < 0 ? best_finished(false) : -1;
    if (best >= 0 && slots_[static_cast<std::size_t>(best)]->long_round) {
      long_index = static_cast<int>(out.tried.size());
      out.tried.push_back(*slots_[static_cast<std::size_t>(best)]->long_round);
    }
    if (out.tried.empty()) return out;
    if (reached_index >= 0) {
      out.scene = reached_index;
      out.reached = true;
    } else if (long_index >= 0 &&
               out.tried[static_cast<std::size_t>(long_index)].heldout_error() <= target()) {
      out.scene = long_index;
      out.reached = true;
    } else {
      out.scene = 0;
      for (std::size_t i = 1; i < out.tried.size(); ++i) {
        if (out.tried[i].heldout_error() < out.tried[static_cast<std::size_t>(out.scene)].heldout_error()) {
          out.scene = static_cast<int>(i);
        }
      }
    }
    return out;
  }

  const SceneDomain& domain_;
  SurfaceKind surface_;
  const SceneStudyOptions& o_;
  const StudyLog& log_;
  TrainingData data_;
  bool long_round_;
  std::vector<std::unique_ptr<Slot>> slots_;
  ThreadPriority priority_;
  std::mutex mutex_;
  std::condition_variable changed_;
  std::size_t next_ = 0;
  int reached_ = -1;  // the smallest size (slot index) that reached the target in the first round
  bool finished_ = false;
};

}  // namespace

NetworkTraining train_networks(const SceneDomain& domain, SurfaceKind surface,
                               const SceneStudyOptions& options, const std::vector<int>& sizes,
                               const StudyLog& log) {
  if (sizes.empty()) return {};
  TrainingSchedule schedule(domain, surface, options, sizes, log);
  return schedule.run();
}

}  // namespace contactnn::study
