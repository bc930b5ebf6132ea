// Little-endian byte streams for solvers' versioned binary state (checkpoints).
// Writing appends to a byte vector: a trivially copyable value as its bytes, an
// array as u64 n + n values, raw doubles. ByteReader reads the same back from a
// byte span (which must outlive it) and checks every size against the bytes that
// remain before anything is copied or allocated; every error is std::runtime_error
//   "<context>: <what> at byte <position> of <size>"
// where context names the format (e.g. "control checkpoint") and size is the whole
// span's, even after set_end() has narrowed where reading stops.
#pragma once
#include <bit>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <span>
#include <string>
#include <type_traits>
#include <vector>

static_assert(std::endian::native == std::endian::little, "byte streams are little-endian");

namespace pliant {

void append_bytes(std::vector<uint8_t>& out, const void* data, size_t size);

template <class T>
void append_value(std::vector<uint8_t>& out, const T& v) {
  static_assert(std::is_trivially_copyable_v<T>);
  append_bytes(out, &v, sizeof(T));
}

// n doubles, no length.
inline void append_doubles(std::vector<uint8_t>& out, const double* p, size_t n) {
  append_bytes(out, p, n * sizeof(double));
}

// u64 length + the values.
template <class T>
void append_array(std::vector<uint8_t>& out, const std::vector<T>& v) {
  static_assert(std::is_trivially_copyable_v<T>);
  append_value<uint64_t>(out, v.size());
  append_bytes(out, v.data(), v.size() * sizeof(T));
}

class ByteReader {
 public:
  ByteReader(std::span<const uint8_t> bytes, std::string context);

  size_t position() const { return pos_; }
  size_t size() const { return bytes_.size(); }
  // Bytes left before the end (the span's end unless set_end moved it).
  size_t remaining() const { return end_ - pos_; }
  // Reading stops at `end` (position <= end <= size; else bad()).
  void set_end(size_t end);

  [[noreturn]] void bad(const std::string& what) const;

  template <class T>
  T get() {
    static_assert(std::is_trivially_copyable_v<T>);
    if (remaining() < sizeof(T)) bad("truncated");
    T v;
    std::memcpy(&v, bytes_.data() + pos_, sizeof(T));
    pos_ += sizeof(T);
    return v;
  }

  // n values of T into out ("truncated" if fewer remain).
  template <class T>
  void get_values(T* out, size_t n) {
    static_assert(std::is_trivially_copyable_v<T>);
    if (n > remaining() / sizeof(T)) bad("truncated");
    get_bytes(out, n * sizeof(T));
  }
  void get_bytes(void* out, size_t size);

  // A u64 length of an array of T that must fit in what remains:
  // "<what> of <n> values longer than the data" if not.
  template <class T>
  uint64_t get_length(const char* what = "array") {
    const uint64_t n = get<uint64_t>();
    if (n > remaining() / sizeof(T)) bad_length(what, n);
    return n;
  }

  // u64 length + the values (append_array's form).
  template <class T>
  std::vector<T> get_array(const char* what = "array") {
    std::vector<T> v(get_length<T>(what));
    get_values(v.data(), v.size());
    return v;
  }

 private:
  [[noreturn]] void bad_length(const char* what, uint64_t n) const;

  std::span<const uint8_t> bytes_;
  std::string context_;
  size_t pos_ = 0, end_ = 0;
};

}  // namespace pliant
