// The extension ipmc_swim._core: the simulation library's runs, analyses
// and one steppable simulation, for the package ipmc_swim
// (sim/python/ipmc_swim/__init__.py documents the calls).
//
// Errors: every error the library reports (bad input, a diverging run, a
// file that cannot be written) is raised as ipmc_swim.Error, a ValueError,
// with the one-line message the command line prints after "ipmc-swim:
// error: ". Wrong Python types are TypeErrors.
#include <pybind11/pybind11.h>

#include <cstring>
#include <exception>
#include <new>
#include <stdexcept>
#include <string>

#include "ipmc_swim/ipmc_swim.h"
#include "sim/python/convert.h"

namespace ipmc::python {
namespace {

void TranslateLibraryErrors(std::exception_ptr error) {
  if (!error) return;
  try {
    std::rethrow_exception(error);
  } catch (const py::error_already_set&) {
    throw;
  } catch (const py::builtin_exception&) {
    throw;
  } catch (const std::bad_alloc&) {
    throw;
  } catch (const std::exception& failure) {
    PyErr_SetString(py::module_::import("ipmc_swim._core").attr("Error").ptr(), failure.what());
  }
}

// The module is built against one version of the library's headers and
// types; another libipmc_swim found at load time (an older install earlier
// on the library path) would run with mismatched structures.
void CheckLibraryVersion() {
  if (std::strcmp(ipmc::Version(), IPMC_SWIM_MODULE_VERSION) == 0) return;
  throw py::import_error(std::string("ipmc_swim: the module ipmc_swim._core is version ") +
                         IPMC_SWIM_MODULE_VERSION + " but the library libipmc_swim it loaded is " +
                         ipmc::Version() +
                         "; rebuild and reinstall both from one source tree (pip install "
                         "sim/python or cmake --install)");
}

}  // namespace
}  // namespace ipmc::python

PYBIND11_MODULE(_core, m) {
  namespace py = pybind11;
  using namespace ipmc::python;
  CheckLibraryVersion();
  m.doc() = "ipmc-swim's simulation library (see the package ipmc_swim)";
  py::exception<std::exception> error(m, "Error", PyExc_ValueError);
  error.doc() =
      "An error the simulator reports: bad input (naming the file, key and allowed range), a "
      "diverging run, an output that cannot be written.";
  py::register_exception_translator(TranslateLibraryErrors);
  InstallMujocoWarningLog();
  m.attr("__version__") = ipmc::Version();
  BindRuns(m);
  BindAnalysis(m);
  BindSimulation(m);
  BindPlot(m);
  BindOptimize(m);
}
