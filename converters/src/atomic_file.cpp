// Outputs that land whole or not at all, and the signal cleanup of their temporaries. See atomic_file.h and
// qualmesh/temporary_files.h.
#include "atomic_file.h"

#include <pthread.h>
#include <signal.h>
#include <sys/stat.h>
#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <random>

#include "qualmesh/error.h"
#include "qualmesh/temporary_files.h"

namespace qualmesh {

// ---------------------------------------------------------------------------------------------------------------
// The table of live temporaries, readable from a signal handler: fixed slots in static storage, each claimed and
// released with atomic stores (lock-free on every target we build for). A temporary that finds no slot (more than
// kNumSlots at once, or a path longer than kPathBytes) still works; only a signal would leave it behind.
namespace {

constexpr int kNumSlots = 64;
constexpr std::size_t kPathBytes = 4096;
enum SlotState : int { kFree = 0, kClaimed = 1, kFile = 2, kDirectory = 3 };

struct Slot {
  std::atomic<int> state{kFree};
  char path[kPathBytes];
};
Slot g_slots[kNumSlots];
std::atomic<bool> g_file_size_limit{false};
static_assert(std::atomic<int>::is_always_lock_free, "the signal handler reads the slots");

int register_temporary(const std::string& path, bool directory) {
  if (path.size() >= kPathBytes) return -1;
  for (int i = 0; i < kNumSlots; ++i) {
    int expected = kFree;
    if (g_slots[i].state.compare_exchange_strong(expected, kClaimed)) {
      std::memcpy(g_slots[i].path, path.c_str(), path.size() + 1);
      g_slots[i].state.store(directory ? kDirectory : kFile);
      return i;
    }
  }
  return -1;
}

void unregister_temporary(int slot) {
  if (slot >= 0) g_slots[slot].state.store(kFree);
}

extern "C" void remove_temporaries_and_reraise(int signal_number) {
  remove_registered_temporaries();
  // Default action, unblocked, raised again: the process ends by this signal, as it would have without us.
  ::signal(signal_number, SIG_DFL);
  sigset_t set;
  sigemptyset(&set);
  sigaddset(&set, signal_number);
  pthread_sigmask(SIG_UNBLOCK, &set, nullptr);
  raise(signal_number);
}

extern "C" void note_file_size_limit(int) { g_file_size_limit.store(true); }

// SIGINT, SIGTERM, SIGHUP: the signals whose handler removes the temporaries, held back while a set is committed.
sigset_t cleanup_signals() {
  sigset_t set;
  sigemptyset(&set);
  sigaddset(&set, SIGINT);
  sigaddset(&set, SIGTERM);
  sigaddset(&set, SIGHUP);
  return set;
}

}  // namespace

void remove_registered_temporaries() noexcept {
  for (int i = kNumSlots - 1; i >= 0; --i) {
    if (g_slots[i].state.load() == kFile) unlink(g_slots[i].path);
  }
  for (int i = kNumSlots - 1; i >= 0; --i) {
    if (g_slots[i].state.load() == kDirectory) rmdir(g_slots[i].path);
  }
}

bool file_size_limit_reached() noexcept { return g_file_size_limit.load(); }

void install_temporary_cleanup_handlers() {
  struct sigaction action;
  std::memset(&action, 0, sizeof action);
  sigemptyset(&action.sa_mask);
  action.sa_handler = remove_temporaries_and_reraise;
  for (int signal_number : {SIGINT, SIGTERM, SIGHUP}) {
    struct sigaction old;
    // A signal the parent set to be ignored (nohup, a background job's SIGINT) stays ignored.
    if (sigaction(signal_number, nullptr, &old) == 0 && old.sa_handler == SIG_IGN) continue;
    sigaction(signal_number, &action, nullptr);
  }
  action.sa_handler = note_file_size_limit;
  sigaction(SIGXFSZ, &action, nullptr);
}

namespace io {

namespace {

namespace fs = std::filesystem;

std::string temporary_name(const std::string& path) {
  // Unique per process and call; no randomness leaks into the output itself.
  static std::mt19937_64 generator{std::random_device{}()};
  static const char* digits = "0123456789abcdefghijklmnopqrstuvwxyz";
  std::string name = path + ".tmp-";
  for (int i = 0; i < 8; ++i) name += digits[generator() % 36];
  return name;
}

void require_parent_folder(const fs::path& target, const std::string& path) {
  if (target.has_parent_path() && !fs::is_directory(target.parent_path())) {
    throw InputError(ErrorCode::Io, "folder '" + target.parent_path().string() + "' does not exist", path);
  }
}

std::string write_failure() {
  return file_size_limit_reached() ? "write failed: the file size limit (ulimit -f) was reached"
                                   : "write failed (disk full?)";
}

// Writes `fill` to `file`, which the caller has registered; errors name `shown` (and `what`, the file inside a
// directory output, when given).
void fill_file(const std::string& file, const std::string& shown, const std::string& what,
               const std::function<void(std::ostream&)>& fill) {
  const std::string prefix = what.empty() ? "" : what + ": ";
  std::ofstream out(file, std::ios::binary | std::ios::trunc);
  if (!out) throw InputError(ErrorCode::Io, prefix + "cannot create file: " + std::strerror(errno), shown);
  fill(out);
  out.flush();
  if (!out) throw InputError(ErrorCode::Io, prefix + write_failure(), shown);
  out.close();
  if (!out) throw InputError(ErrorCode::Io, prefix + write_failure(), shown);
}

bool exists_no_follow(const std::string& path, struct stat& st) { return lstat(path.c_str(), &st) == 0; }

}  // namespace

struct OutputSet::Entry {
  std::string target;
  std::string temp;
  bool directory = false;
  int slot = -1;
  std::vector<std::pair<std::string, int>> inside;  // files of a directory output, with their slots
  std::string backup;                               // the old target kept aside during commit
  int backup_slot = -1;
  bool backup_is_link = false;  // a hard link (the target stays in place) rather than the target renamed away
  bool placed = false;          // renamed into place
};

OutputSet::OutputSet() = default;

OutputSet::~OutputSet() {
  if (!committed_) discard();
}

void OutputSet::discard() noexcept {
  std::error_code ignored;
  for (auto it = entries_.rbegin(); it != entries_.rend(); ++it) {
    Entry& e = **it;
    for (auto& [file, slot] : e.inside) {
      unlink(file.c_str());
      unregister_temporary(slot);
    }
    e.inside.clear();
    if (!e.placed) {
      if (e.directory) fs::remove_all(e.temp, ignored);
      else unlink(e.temp.c_str());
    }
    unregister_temporary(e.slot);
    e.slot = -1;
  }
  entries_.clear();
}

void OutputSet::write_file(const std::string& path, const std::function<void(std::ostream&)>& fill) {
  require_parent_folder(fs::path(path), path);
  auto entry = std::make_unique<Entry>();
  entry->target = path;
  entry->temp = temporary_name(path);
  entry->slot = register_temporary(entry->temp, false);  // before the file exists, so no signal can miss it
  Entry& e = *entry;
  entries_.push_back(std::move(entry));
  fill_file(e.temp, path, "", fill);
}

std::string OutputSet::write_directory(const std::string& path) {
  std::string clean = path;
  while (clean.size() > 1 && clean.back() == '/') clean.pop_back();
  require_parent_folder(fs::path(clean), path);
  auto entry = std::make_unique<Entry>();
  entry->target = clean;
  entry->temp = temporary_name(clean);
  entry->directory = true;
  entry->slot = register_temporary(entry->temp, true);
  Entry& e = *entry;
  entries_.push_back(std::move(entry));
  std::error_code ec;
  if (!fs::create_directory(e.temp, ec)) {
    throw InputError(ErrorCode::Io, "cannot create directory " + e.temp + ": " + ec.message(), path);
  }
  return e.temp;
}

void OutputSet::write_inside(const std::string& temp_dir, const std::string& name, const std::string& target,
                             const std::function<void(std::ostream&)>& fill) {
  Entry* owner = nullptr;
  for (auto& e : entries_) {
    if (e->directory && e->temp == temp_dir) owner = e.get();
  }
  if (!owner) throw std::logic_error("OutputSet::write_inside: not a directory of this set: " + temp_dir);
  const std::string file = temp_dir + "/" + name;
  owner->inside.emplace_back(file, register_temporary(file, false));
  fill_file(file, target, name, fill);
}

void OutputSet::commit() {
  // Nothing a signal could interrupt half way: SIGINT, SIGTERM and SIGHUP wait until the renames are done or undone.
  const sigset_t held = cleanup_signals();
  sigset_t previous;
  pthread_sigmask(SIG_BLOCK, &held, &previous);
  struct RestoreMask {
    sigset_t mask;
    ~RestoreMask() { pthread_sigmask(SIG_SETMASK, &mask, nullptr); }
  } restore{previous};

  const auto fail = [this](std::string message, std::string path) {  // copies: discard() frees the entries
    // Undo in reverse: a placed target gets its old file back (or goes, when there was none); a target renamed
    // aside comes back.
    std::error_code ignored;
    for (auto it = entries_.rbegin(); it != entries_.rend(); ++it) {
      Entry& e = **it;
      if (e.placed) {
        if (!e.backup.empty()) {
          if (e.directory) fs::remove_all(e.target, ignored);  // rename(2) does not replace a full directory
          std::rename(e.backup.c_str(), e.target.c_str());
        } else if (e.directory) {
          fs::remove_all(e.target, ignored);
        } else {
          unlink(e.target.c_str());
        }
        e.placed = false;
        e.inside.clear();  // moved with the directory, gone with it
        unregister_temporary(e.backup_slot);
        e.backup.clear();
        continue;
      }
      if (!e.backup.empty()) {
        if (e.backup_is_link) unlink(e.backup.c_str());
        else std::rename(e.backup.c_str(), e.target.c_str());
        unregister_temporary(e.backup_slot);
        e.backup.clear();
      }
    }
    discard();
    throw InputError(ErrorCode::Io, message, path);
  };

  // 1. Every target checked, and the existing ones kept aside.
  for (auto& entry : entries_) {
    Entry& e = *entry;
    struct stat st;
    if (!exists_no_follow(e.target, st)) continue;
    const bool is_dir = S_ISDIR(st.st_mode);
    if (e.directory && !is_dir) fail("exists and is not a directory", e.target);
    if (!e.directory && is_dir) fail("is a directory: nothing written", e.target);
    e.backup = temporary_name(e.target);
    e.backup_slot = register_temporary(e.backup, false);
    if (!e.directory && link(e.target.c_str(), e.backup.c_str()) == 0) {
      e.backup_is_link = true;
    } else if (std::rename(e.target.c_str(), e.backup.c_str()) != 0) {
      const std::string why = std::strerror(errno);
      unregister_temporary(e.backup_slot);
      e.backup.clear();
      fail("cannot keep the existing file aside: " + why, e.target);
    }
    if (e.directory) {  // a signal now would find the old directory under the backup name: keep it out of reach
      unregister_temporary(e.backup_slot);
      e.backup_slot = -1;
    }
  }
  // 2. All renamed into place.
  for (auto& entry : entries_) {
    Entry& e = *entry;
    if (std::rename(e.temp.c_str(), e.target.c_str()) != 0) {
      fail(std::string("cannot rename the temporary ") + (e.directory ? "directory" : "file") +
               " into place: " + std::strerror(errno) + " (nothing of this output was written)",
           e.target);
    }
    e.placed = true;
  }
  // 3. The old files go.
  std::error_code ignored;
  for (auto& entry : entries_) {
    Entry& e = *entry;
    if (!e.backup.empty()) {
      if (e.directory) fs::remove_all(e.backup, ignored);
      else unlink(e.backup.c_str());
    }
    unregister_temporary(e.backup_slot);
    for (auto& [file, slot] : e.inside) unregister_temporary(slot);
    unregister_temporary(e.slot);
  }
  committed_ = true;
}

void write_file_atomically(const std::string& path, const std::function<void(std::ostream&)>& fill) {
  OutputSet set;
  set.write_file(path, fill);
  set.commit();
}

}  // namespace io
}  // namespace qualmesh
