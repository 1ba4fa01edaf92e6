// carom's errors in Python: bad input and bad arguments are ValueErrors (InputError names the
// file and line; a RequestError names the options as Python's keywords, kT=), a run that cannot
// go on is a RuntimeError (JamError).
#include <stdexcept>
#include <string>

#include "carom/engine/engine.hpp"
#include "carom/io/classic_input.hpp"
#include "carom/run/request.hpp"
#include "exports.hpp"
#include "specs.hpp"

namespace carom::python {

namespace py = pybind11;

void export_errors(py::module_& m) {
  static const py::exception<InputError>& input_error =
      py::register_exception<InputError>(m, "InputError", PyExc_ValueError);
  static const py::exception<JamError>& jam_error =
      py::register_exception<JamError>(m, "JamError", PyExc_RuntimeError);
  // pybind11 sets an exception's message with PyErr_SetString, which cannot decode one that is
  // not UTF-8 (a file name in Latin-1): the error would reach Python without its message. Such a
  // message is decoded as os.fsdecode decodes a name (surrogateescape), so the name survives, into
  // the Python type pybind11 gives the exception. A RequestError is worded with Python's keywords.
  // Registered last, this translator runs first.
  py::register_exception_translator([](std::exception_ptr thrown) {
    try {
      std::rethrow_exception(thrown);
    } catch (const py::error_already_set&) {
      throw;
    } catch (const py::builtin_exception&) {
      throw;
    } catch (const std::exception& e) {
      const auto* request = dynamic_cast<const RequestError*>(&e);
      const std::string what = request != nullptr ? request->worded(python_keyword) : e.what();
      PyObject* strict =
          PyUnicode_DecodeUTF8(what.data(), static_cast<Py_ssize_t>(what.size()), nullptr);
      if (strict != nullptr) Py_DECREF(strict);
      if (strict != nullptr && request == nullptr) throw;  // UTF-8: the usual translation
      PyErr_Clear();
      const py::object message = py::reinterpret_steal<py::object>(PyUnicode_DecodeUTF8(
          what.data(), static_cast<Py_ssize_t>(what.size()), "surrogateescape"));
      PyObject* type = PyExc_RuntimeError;
      if (dynamic_cast<const InputError*>(&e) != nullptr) {
        type = input_error.ptr();
      } else if (dynamic_cast<const JamError*>(&e) != nullptr) {
        type = jam_error.ptr();
      } else if (dynamic_cast<const std::out_of_range*>(&e) != nullptr) {
        type = PyExc_IndexError;
      } else if (dynamic_cast<const std::overflow_error*>(&e) != nullptr) {
        type = PyExc_OverflowError;
      } else if (dynamic_cast<const std::invalid_argument*>(&e) != nullptr ||
                 dynamic_cast<const std::domain_error*>(&e) != nullptr ||
                 dynamic_cast<const std::length_error*>(&e) != nullptr ||
                 dynamic_cast<const std::range_error*>(&e) != nullptr) {
        type = PyExc_ValueError;
      }
      PyErr_SetObject(type, message.ptr());
    }
  });
}

}  // namespace carom::python
