#include "event_arrays.hpp"

#include <fmt/format.h>

#include <string>

namespace py = pybind11;

namespace asynevo::python {

void addColumns(const EventChunks& chunks, py::dict& out) {
  std::size_t n = 0;
  for (const auto& chunk : chunks) n += chunk.size();
  const auto size = static_cast<py::ssize_t>(n);
  py::array_t<int64_t> t(size);
  py::array_t<uint16_t> x(size), y(size);
  py::array_t<int8_t> p(size);
  int64_t* pt = t.mutable_data();
  uint16_t* px = x.mutable_data();
  uint16_t* py_ = y.mutable_data();
  int8_t* pp = p.mutable_data();
  {
    py::gil_scoped_release release;
    std::size_t i = 0;
    for (const auto& chunk : chunks) {
      for (const Event& e : chunk) {
        pt[i] = e.t_ns;
        px[i] = e.x;
        py_[i] = e.y;
        pp[i] = e.polarity;
        ++i;
      }
    }
  }
  out["t"] = t;
  out["x"] = x;
  out["y"] = y;
  out["p"] = p;
}

namespace {

std::string dtypeName(const py::array& a) { return py::str(a.dtype()).cast<std::string>(); }

/// `obj` as a 1-D numpy array of an integer (or, for polarities, bool) dtype.
py::array integerColumn(const py::handle& obj, const char* name, bool allow_bool) {
  py::array a = py::array::ensure(obj);
  if (!a) throw py::value_error(fmt::format("{} is not an array (numpy array or sequence of numbers)", name));
  if (a.ndim() != 1)
    throw py::value_error(fmt::format("{} must be one-dimensional, not {}-dimensional", name, a.ndim()));
  const char kind = a.dtype().kind();
  // An empty array (e.g. from an empty list, float64) has no values to misread.
  const bool ok = kind == 'i' || kind == 'u' || (allow_bool && kind == 'b') || a.size() == 0;
  if (!ok) {
    if (name[0] == 't')
      throw py::value_error(
          fmt::format("t has dtype {}: event times are integer nanoseconds (int64), e.g. "
                      "numpy.round(t_s * 1e9).astype(numpy.int64)",
                      dtypeName(a)));
    throw py::value_error(
        fmt::format("{} has dtype {}: {} must be {}", name, dtypeName(a), name,
                    allow_bool ? "bool or integers (1 ON, 0 or -1 OFF)" : "integers (pixels)"));
  }
  return a;
}

template <class T, class F>
bool visitAs(const py::array& a, F& f) {
  if (!py::isinstance<py::array_t<T>>(a)) return false;
  auto c = py::array_t<T, py::array::c_style>::ensure(a);  // copies only a strided view
  f(c.data(), static_cast<std::size_t>(c.size()));
  return true;
}

/// Calls f(const T* data, n) with the array's own element type (no conversion of the whole column).
template <class F>
void visitInteger(const py::array& a, const char* name, F&& f) {
  if (a.size() == 0) return;
  if (visitAs<int64_t>(a, f) || visitAs<uint16_t>(a, f) || visitAs<int8_t>(a, f) || visitAs<bool>(a, f) ||
      visitAs<int32_t>(a, f) || visitAs<uint32_t>(a, f) || visitAs<int16_t>(a, f) || visitAs<uint8_t>(a, f) ||
      visitAs<uint64_t>(a, f))
    return;
  throw py::value_error(fmt::format("{} has dtype {}, which is not supported", name, dtypeName(a)));
}

}  // namespace

std::vector<Event> eventsFromArrays(const py::handle& t_obj, const py::handle& x_obj, const py::handle& y_obj,
                                    const py::handle& p_obj, int width, int height) {
  if (width <= 0 || height <= 0)
    throw py::value_error(fmt::format("the sensor size must be positive, not {}x{}", width, height));
  const py::array t = integerColumn(t_obj, "t", false);
  const py::array x = integerColumn(x_obj, "x", false);
  const py::array y = integerColumn(y_obj, "y", false);
  const py::array p = integerColumn(p_obj, "p", true);
  const auto n = static_cast<std::size_t>(t.size());
  const std::pair<const char*, const py::array*> others[] = {{"x", &x}, {"y", &y}, {"p", &p}};
  for (const auto& [name, a] : others)
    if (static_cast<std::size_t>(a->size()) != n)
      throw py::value_error(fmt::format(
          "{} has {} elements but t has {}: t, x, y and p must have the same length", name, a->size(), n));

  std::vector<Event> events(n);
  visitInteger(t, "t", [&](const auto* data, std::size_t) {
    for (std::size_t i = 0; i < n; ++i) {
      const auto v = data[i];
      if constexpr (std::is_same_v<std::decay_t<decltype(v)>, uint64_t>) {
        if (v > static_cast<uint64_t>(INT64_MAX))
          throw py::value_error(fmt::format("t[{}] = {} does not fit int64", i, v));
      }
      events[i].t_ns = static_cast<int64_t>(v);
      if (i > 0 && events[i].t_ns < events[i - 1].t_ns)
        throw py::value_error(fmt::format("t is not sorted: t[{}] = {} is earlier than t[{}] = {}", i,
                                          events[i].t_ns, i - 1, events[i - 1].t_ns));
    }
  });
  auto pixels = [&](const py::array& a, const char* name, int size, const char* dimension, auto set) {
    visitInteger(a, name, [&](const auto* data, std::size_t) {
      for (std::size_t i = 0; i < n; ++i) {
        const auto v = static_cast<int64_t>(data[i]);
        if (v < 0 || v >= size)
          throw py::value_error(fmt::format("{}[{}] = {} is outside the sensor ({} {}: 0 .. {})", name, i, v,
                                            dimension, size, size - 1));
        set(events[i], static_cast<uint16_t>(v));
      }
    });
  };
  pixels(x, "x", width, "width", [](Event& e, uint16_t v) { e.x = v; });
  pixels(y, "y", height, "height", [](Event& e, uint16_t v) { e.y = v; });
  visitInteger(p, "p", [&](const auto* data, std::size_t) {
    for (std::size_t i = 0; i < n; ++i) {
      const auto v = static_cast<int64_t>(data[i]);
      if (v != 1 && v != 0 && v != -1)
        throw py::value_error(fmt::format("p[{}] = {} is not a polarity (1 ON, 0 or -1 OFF)", i, v));
      events[i].polarity = v == 1 ? int8_t{1} : int8_t{-1};
    }
  });
  return events;
}

}  // namespace asynevo::python
