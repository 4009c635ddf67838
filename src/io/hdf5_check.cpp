// CheckH5FileInChildProcess: the last layer of the HDF5 defence. libhdf5
// 1.10.8 can crash on corrupt files (global-heap and vlen conversion reads,
// huge cache allocations) before bridgefit's own checks can see anything, so
// a file named on the command line is first read, completely, in a forked
// child; only a file that child survives is opened in this process.
#include <H5Cpp.h>
#include <signal.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>
#include <fcntl.h>

#include <array>
#include <chrono>
#include <cstring>
#include <fstream>
#include <thread>

#include <fmt/format.h>

#include "bridgefit/core/error.hpp"
#include "bridgefit/core/interrupt.hpp"
#include "bridgefit/io/hdf5.hpp"
#include "hdf5_checked.hpp"

#if defined(__has_feature)
#if __has_feature(address_sanitizer) || __has_feature(memory_sanitizer)
#define BRIDGEFIT_SANITIZED 1
#endif
#endif
#if defined(__SANITIZE_ADDRESS__)
#define BRIDGEFIT_SANITIZED 1
#endif
#ifdef BRIDGEFIT_SANITIZED
#include <sanitizer/common_interface_defs.h>
#endif

namespace bridgefit::io {
namespace {

// Child exit codes.
constexpr int kChildOk = 0;
constexpr int kChildRefused = 3;  // refused; the reason goes through the pipe
constexpr std::uint64_t kMaxObjects = 100'000;
constexpr std::uint64_t kMaxAttributesPerObject = 10'000;
// Least extra address space the child gets beyond what it has at the fork.
constexpr std::uint64_t kChildRoom = std::uint64_t{512} << 20;

struct Walk {
  const H5::H5File* file;
  const H5Checked* checked;
  std::uint64_t objects = 0;
  int failure = kChildOk;  // set by the callback, which must not throw through C
  std::string message;     // the refusal, for the parent
};

// The parent names the file itself.
std::string WithoutFile(const Error& e) {
  ErrorContext context = e.context();
  context.file.clear();
  context.expected.clear();
  return FormatErrorMessage(e.message(), context);
}

void ReadAttributes(H5::H5Object& object, const std::string& path, const H5Checked& checked) {
  const int count = object.getNumAttrs();
  if (count < 0 || static_cast<std::uint64_t>(count) > kMaxAttributesPerObject)
    throw Error(ErrorKind::kInput, "too many attributes", {.field = path});
  for (int i = 0; i < count; ++i) {
    const H5::Attribute attribute = object.openAttribute(static_cast<unsigned>(i));
    const std::string field = path + "@" + attribute.getName();
    const H5T_class_t type_class = attribute.getDataType().getClass();
    if (type_class == H5T_STRING) checked.ReadTextAttribute(attribute, field);
    else if (type_class == H5T_FLOAT || type_class == H5T_INTEGER)
      checked.ReadNumberAttribute(attribute, field);
  }
}

void VisitOneOrThrow(Walk& walk, const char* name, const H5O_info_t* info) {
  if (++walk.objects > kMaxObjects)
    throw Error(ErrorKind::kInput, "more than 100000 objects in the file");
  const std::string path = std::string("/") + (std::strcmp(name, ".") == 0 ? "" : name);
  if (info->type == H5O_TYPE_GROUP) {
    H5::Group group = walk.file->openGroup(path);
    ReadAttributes(group, path, *walk.checked);
  } else if (info->type == H5O_TYPE_DATASET) {
    H5::DataSet dataset = walk.file->openDataSet(path);
    ReadAttributes(dataset, path, *walk.checked);
    const H5T_class_t type_class = dataset.getDataType().getClass();
    if (type_class == H5T_STRING) walk.checked->ReadTexts(dataset, path);
    else if (type_class == H5T_FLOAT || type_class == H5T_INTEGER)
      walk.checked->ReadNumbers(dataset, path);
    else
      walk.checked->CheckedExtent(dataset, path, dataset.getDataType().getSize());
  }
}

herr_t VisitOne(hid_t, const char* name, const H5O_info_t* info, void* data) {
  Walk& walk = *static_cast<Walk*>(data);
  try {
    VisitOneOrThrow(walk, name, info);
    return 0;
  } catch (const Error& e) {
    walk.failure = kChildRefused;
    walk.message = WithoutFile(e);
  } catch (const H5::Exception& e) {
    walk.failure = kChildRefused;
    walk.message = std::string("cannot read object /") + name + ": " + e.getDetailMsg();
  } catch (const std::bad_alloc&) {
    walk.failure = kChildRefused;
    walk.message = std::string("object /") + name + " asks for more memory than any intact file";
  }
  return -1;
}

// Runs in the child: reads everything; returns the exit code and, for a
// refusal, its message in *message.
int ReadEverything(const std::filesystem::path& path, std::string* message) {
  try {
    H5::Exception::dontPrint();
    std::error_code ec;
    const std::uint64_t bytes = std::filesystem::file_size(path, ec);
    if (ec) return kChildOk;  // the parent's reader reports it
    const H5Checked checked(path.string(), bytes, InputLimits::FromEnvironment());
    if (!H5::H5File::isHdf5(path.string())) return kChildOk;
    const H5::H5File file(path.string(), H5F_ACC_RDONLY);
    Walk walk{&file, &checked};
    if (H5Ovisit2(file.getId(), H5_INDEX_NAME, H5_ITER_NATIVE, VisitOne, &walk,
                  H5O_INFO_BASIC) < 0 && walk.failure == kChildOk) {
      walk.failure = kChildRefused;
      walk.message = "libhdf5 cannot walk the file's groups";
    }
    *message = walk.message;
    return walk.failure;
  } catch (const Error& e) {
    *message = WithoutFile(e);
    return kChildRefused;
  } catch (const H5::Exception& e) {
    *message = "cannot open: " + e.getDetailMsg();
    return kChildRefused;
  } catch (const std::bad_alloc&) {
    *message = "a size in the file asks for more memory than any intact file";
    return kChildRefused;
  } catch (...) {
    return 5;
  }
}

// Current address-space size of this process, bytes (0 when unknown).
std::uint64_t AddressSpaceBytes() {
  std::ifstream statm("/proc/self/statm");
  std::uint64_t pages = 0;
  statm >> pages;
  return pages * static_cast<std::uint64_t>(::sysconf(_SC_PAGESIZE));
}

[[noreturn]] void RunChild(const std::filesystem::path& path, double timeout_s, int report_fd,
                           const std::function<void()>& also_read) {
  // Default dispositions: a crash must end the child by its signal, not run
  // handlers inherited from the parent (sanitizers, fuzzers, the CLI).
  for (int s : {SIGSEGV, SIGBUS, SIGABRT, SIGFPE, SIGILL, SIGINT, SIGTERM})
    ::signal(s, SIG_DFL);
  sigset_t all;
  sigemptyset(&all);
  pthread_sigmask(SIG_SETMASK, &all, nullptr);
#ifdef BRIDGEFIT_SANITIZED
  __sanitizer_set_death_callback(nullptr);
#else
  // What the process has now, plus room for what reading this file can
  // honestly need: unfiltered data cannot exceed the file's size, and 512 MiB
  // covers well-compressed data too. A size field asking for more (a vlen
  // string claiming gigabytes) fails here, as a refusal, in milliseconds
  // instead of a multi-GB memset.
  std::error_code ec;
  const std::uint64_t file_bytes = std::filesystem::file_size(path, ec);
  const std::uint64_t largest = InputLimits::FromEnvironment().max_dataset_elements * 12;
  const std::uint64_t need = std::min(largest, std::max(kChildRoom, 64 * file_bytes));
  const rlim_t room = static_cast<rlim_t>(AddressSpaceBytes() + need);
  const rlimit memory{room, room};
  setrlimit(RLIMIT_AS, &memory);
#endif
  const rlim_t cpu = static_cast<rlim_t>(timeout_s) + 1;
  const rlimit cpu_limit{cpu, cpu};
  setrlimit(RLIMIT_CPU, &cpu_limit);
  const int null = ::open("/dev/null", O_WRONLY);
  if (null >= 0) {
    ::dup2(null, STDOUT_FILENO);
    ::dup2(null, STDERR_FILENO);
  }
  std::string message;
  int code = ReadEverything(path, &message);
  if (code == kChildOk && also_read) {
    try {
      also_read();
    } catch (const Error& e) {
      message = WithoutFile(e);
      code = kChildRefused;
    } catch (const std::bad_alloc&) {
      message = "a size in the file asks for more memory than any intact file";
      code = kChildRefused;
    } catch (...) {
      code = 5;
    }
  }
  if (!message.empty()) {
    const ssize_t ignored = ::write(report_fd, message.data(), std::min<std::size_t>(message.size(), 4000));
    (void)ignored;
  }
  ::_exit(code);
}

}  // namespace

bool HasHdf5Signature(const std::filesystem::path& path) {
  static constexpr std::array<char, 8> kSignature = {'\x89', 'H', 'D', 'F', '\r', '\n', '\x1a', '\n'};
  std::error_code ec;
  if (!std::filesystem::is_regular_file(path, ec)) return false;
  std::ifstream stream(path, std::ios::binary);
  // The superblock is at 0 or at 512, 1024, 2048, ... (a user block before it).
  for (std::uint64_t offset = 0; offset < (std::uint64_t{1} << 32); offset = offset ? offset * 2 : 512) {
    std::array<char, 8> head{};
    stream.seekg(static_cast<std::streamoff>(offset));
    if (!stream.read(head.data(), head.size())) return false;
    if (head == kSignature) return true;
  }
  return false;
}

void CheckH5FileInChildProcess(const std::filesystem::path& path, double timeout_s,
                               const std::function<void()>& also_read) {
  // A file that is not HDF5 (a MAT v5 file read by `also_read`) is named so.
  const bool hdf5 = HasHdf5Signature(path);
  const char* corrupt = hdf5 ? "corrupt HDF5 file" : "corrupt file";
  const char* intact = hdf5 ? "an intact HDF5 file" : "an intact file";
  int report[2];
  if (::pipe(report) != 0)
    throw Error(ErrorKind::kRuntime, "cannot start the HDF5 checking process (pipe)",
                {.file = path.string()});
  const pid_t child = ::fork();
  if (child < 0) {
    ::close(report[0]);
    ::close(report[1]);
    throw Error(ErrorKind::kRuntime, std::string("cannot start the HDF5 checking process: ") +
                                         std::strerror(errno),
                {.file = path.string()});
  }
  if (child == 0) {
    ::close(report[0]);
    RunChild(path, timeout_s, report[1], also_read);
  }
  ::close(report[1]);
  struct CloseOnExit {
    int fd;
    ~CloseOnExit() { ::close(fd); }
  } close_report{report[0]};

  const auto start = std::chrono::steady_clock::now();
  auto pause = std::chrono::microseconds(200);
  int status = 0;
  for (;;) {
    const pid_t done = ::waitpid(child, &status, WNOHANG);
    if (done == child) break;
    if (done < 0 && errno != EINTR)
      throw Error(ErrorKind::kRuntime, "lost the HDF5 checking process", {.file = path.string()});
    const double waited =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    if (waited > timeout_s || InterruptRequested()) {
      ::kill(child, SIGKILL);
      ::waitpid(child, &status, 0);
      ThrowIfInterrupted("checking " + path.string());
      throw Error(ErrorKind::kInput,
                  fmt::format("{}: {} (reading it took over {:g} s)", corrupt, path.string(),
                              timeout_s),
                  {.expected = intact});
    }
    std::this_thread::sleep_for(pause);
    pause = std::min(pause * 2, std::chrono::microseconds(20'000));
  }
  if (WIFEXITED(status) && WEXITSTATUS(status) == kChildOk) return;
  if (WIFEXITED(status) && WEXITSTATUS(status) == kChildRefused) {
    // The child's refusal stands: reading the file again here could repeat
    // a huge allocation the child was stopped from making.
    std::string message(4000, '\0');
    const ssize_t n = ::read(report[0], message.data(), message.size());
    message.resize(n > 0 ? static_cast<std::size_t>(n) : 0);
    if (message.empty()) message = "cannot read the file";
    if (message.back() == '.') message.pop_back();
    throw Error(ErrorKind::kInput, std::string(corrupt) + ": " + path.string() + ": " + message,
                {.expected = intact});
  }
  const std::string how = WIFSIGNALED(status)
                              ? fmt::format("libhdf5 crashed reading it, signal {}",
                                            WTERMSIG(status))
                              : fmt::format("reading it failed, status {}", WEXITSTATUS(status));
  throw Error(ErrorKind::kInput, fmt::format("{}: {} ({})", corrupt, path.string(), how),
              {.expected = std::string(intact) + "; re-create it or copy it again"});
}

}  // namespace bridgefit::io
