#include "gil.h"

#include <chrono>
#include <thread>

namespace edgedeform::bindings {

bool interpreter_finalizing() {
#if PY_VERSION_HEX >= 0x030D0000
  return Py_IsFinalizing() != 0;
#else
  return _Py_IsFinalizing() != 0;
#endif
}

void return_to_python(PyThreadState* state) {
  if (interpreter_finalizing())
    for (;;) std::this_thread::sleep_for(std::chrono::hours(24));  // until the process ends
  PyEval_RestoreThread(state);
}

}  // namespace edgedeform::bindings
