// The C++ ABI's throw for wasm32-wasi builds of the certification driver.
//
// Debian's wasm32-wasi libc++abi (libc++abi-14-dev-wasm32) is built without
// exception support: WASI has no stack unwinding, so `throw` links against
// symbols nothing provides. The fixed engine throws only on bad input or a
// RunError (a body leaving the Q16.16 range), which no built-in scene raises on
// any other build (the vectors hold every frame). Here a throw ends the program
// at once, naming the exception's type on stderr, with exit status 3: certify.py
// then reports the build as failed to run ("run failed (exit 3)"), never as
// certified. Linked into the wasm32-wasi builds only (certify.py).
#include <cstdio>
#include <cstdlib>
#include <typeinfo>

extern "C" {

void* __cxa_allocate_exception(std::size_t size) noexcept {
  void* p = std::malloc(size);
  if (p == nullptr) {
    std::fputs("lockstep_certify_driver (wasm32-wasi): out of memory allocating an exception\n", stderr);
    std::_Exit(3);
  }
  return p;
}

[[noreturn]] void __cxa_throw(void* /*object*/, std::type_info* type, void (* /*destructor*/)(void*)) {
  std::fflush(stdout);
  std::fprintf(stderr,
               "lockstep_certify_driver (wasm32-wasi): exception of type %s thrown; wasm32-wasi has no unwinding, "
               "so the run stops here (exit 3)\n",
               type != nullptr ? type->name() : "unknown");
  std::_Exit(3);
}

}  // extern "C"
