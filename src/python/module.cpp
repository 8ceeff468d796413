// The Python module `wavepath` (bindings.h; docs/python.md).
#include <CLI/CLI.hpp>

#include <cerrno>
#include <filesystem>

#include "python/bindings.h"
#include "render/partial.h"
#include "util/error.h"

namespace wp::python {

bool is_missing(const std::string& path) {
  std::error_code ec;
  return !path.empty() && !std::filesystem::exists(path, ec);
}

void raise_file_not_found(const std::string& path, const std::string& message) {
  // FileNotFoundError(errno, message, filename), as open() raises it.
  py::object error = py::module_::import("builtins").attr("FileNotFoundError")(ENOENT, message, path);
  PyErr_SetObject(PyExc_FileNotFoundError, error.ptr());
  throw py::error_already_set();
}

std::string path_of(const py::handle& path) {
  if (!py::isinstance<py::str>(path) && !py::hasattr(path, "__fspath__"))
    throw py::type_error("expected a path (str or os.PathLike), got " + std::string(py::str(py::type::of(path).attr("__name__"))));
  return py::str(py::module_::import("os").attr("fspath")(path));
}

}  // namespace wp::python

PYBIND11_MODULE(wavepath, m) {
  using namespace wp;
  using namespace wp::python;
  m.doc() =
      "wavepath: a physically based path tracer on Vulkan compute kernels, with a CPU reference renderer.\n\n"
      "load() a scene, render() it (GIL released), and read its images as NumPy arrays; merge(), compare(),\n"
      "devices(), variants() and bench() do what the command line's commands of those names do. See docs/python.md.";
  m.attr("__version__") = WAVEPATH_VERSION;
  // Its images are NumPy arrays: without NumPy, say which interpreter
  // lacks it (a python3 earlier on PATH than Debian's often does).
  try {
    py::module_::import("numpy");
  } catch (py::error_already_set& e) {
    if (!e.matches(PyExc_ImportError)) throw;
    throw py::import_error("wavepath needs NumPy, which " + py::str(py::module_::import("sys").attr("executable")).cast<std::string>() +
                           " lacks: run Debian's /usr/bin/python3 (python3-numpy), or install numpy for this interpreter");
  }

  // Errors as the command line reports them: bad input (a file, a JSON
  // path, an option) ValueError with its one line; the device or the
  // environment RuntimeError. Neither ends the interpreter.
  py::register_exception_translator([](std::exception_ptr p) {
    try {
      if (p) std::rethrow_exception(p);
    } catch (const InputError& e) {
      PyErr_SetString(PyExc_ValueError, e.what());
    } catch (const CLI::ParseError& e) {
      PyErr_SetString(PyExc_ValueError, e.what());
    } catch (const RenderError& e) {
      PyErr_SetString(PyExc_RuntimeError, e.what());
    } catch (const vk::SystemError& e) {
      PyErr_SetString(PyExc_RuntimeError, (std::string("Vulkan: ") + e.what()).c_str());
    }
  });

  bind_scene(m);
  bind_render(m);
  bind_tools(m);
}
