// Parsing JSON from users' files: nesting deeper than a limit is refused as
// it is read, and an observer sees each object open and close and each key,
// in order, to check what the finished value cannot show (a key given twice).
//
// Why not nlohmann's parse callback, which offers the same: its parser
// searches the enclosing array for a discarded element every time an object
// or array inside it closes, so an array of n objects takes time in n^2 (a
// glTF with 100,000 nodes spent 2 s there, 70 s under AddressSanitizer).
// This forwards nlohmann's SAX events to its own DOM builder, which is linear
// and iterative, and counts depth on the way. Header-only, free of any Bounce
// type: the GI library and the scene importer both use it.
#pragma once

#include <cstddef>
#include <stdexcept>
#include <string>
#include <type_traits>
#include <utility>

#include <nlohmann/json.hpp>

namespace bounce::util {

// Thrown for a container nested inside `limit` others.
struct JsonTooDeep : std::runtime_error {
  explicit JsonTooDeep(int limit)
      : std::runtime_error("JSON nested deeper than " + std::to_string(limit) + " levels") {}
};

// An observer has all three: objectStart() before an object's first key,
// objectEnd() after its last value, key(name) for each key. This one, the
// default, ignores them.
struct NoJsonObserver {
  void objectStart() {}
  void objectEnd() {}
  void key(const std::string&) {}
};

namespace detail {

template <class Observer>
class DepthLimitedSax {
 public:
  using json = nlohmann::json;

  DepthLimitedSax(json& result, int maxDepth, Observer& observer)
      : builder_(result, true), maxDepth_(maxDepth), observer_(observer) {}

  bool null() { return builder_.null(); }
  bool boolean(bool value) { return builder_.boolean(value); }
  bool number_integer(json::number_integer_t value) { return builder_.number_integer(value); }
  bool number_unsigned(json::number_unsigned_t value) { return builder_.number_unsigned(value); }
  bool number_float(json::number_float_t value, const json::string_t& text) {
    return builder_.number_float(value, text);
  }
  bool string(json::string_t& value) { return builder_.string(value); }
  bool binary(json::binary_t& value) { return builder_.binary(value); }
  bool start_object(std::size_t elements) {
    open();
    observer_.objectStart();
    return builder_.start_object(elements);
  }
  bool key(json::string_t& name) {
    observer_.key(name);
    return builder_.key(name);
  }
  bool end_object() {
    --depth_;
    observer_.objectEnd();
    return builder_.end_object();
  }
  bool start_array(std::size_t elements) {
    open();
    return builder_.start_array(elements);
  }
  bool end_array() {
    --depth_;
    return builder_.end_array();
  }
  template <class Exception>
  bool parse_error(std::size_t position, const std::string& token, const Exception& error) {
    return builder_.parse_error(position, token, error);
  }

 private:
  void open() {
    if (depth_ >= maxDepth_) throw JsonTooDeep(maxDepth_);
    ++depth_;
  }

  nlohmann::detail::json_sax_dom_parser<json> builder_;
  int depth_ = 0;  // containers open around the next value
  int maxDepth_;
  Observer& observer_;
};

}  // namespace detail

// Parses `input` (anything nlohmann::json::sax_parse reads: a string, a
// stream, a pair of iterators through parseJson(first, last, ...)) into a
// value. At most maxDepth containers may be open at once; one more throws
// JsonTooDeep before it is built. Bad JSON throws nlohmann's parse_error.
template <class Input, class Observer = NoJsonObserver>
nlohmann::json parseJson(Input&& input, int maxDepth, Observer&& observer = {}) {
  nlohmann::json result;
  detail::DepthLimitedSax<std::remove_reference_t<Observer>> sax(result, maxDepth, observer);
  nlohmann::json::sax_parse(std::forward<Input>(input), &sax);
  return result;
}

template <class Iterator, class Observer = NoJsonObserver>
nlohmann::json parseJson(Iterator first, Iterator last, int maxDepth, Observer&& observer = {}) {
  nlohmann::json result;
  detail::DepthLimitedSax<std::remove_reference_t<Observer>> sax(result, maxDepth, observer);
  nlohmann::json::sax_parse(first, last, &sax);
  return result;
}

}  // namespace bounce::util
