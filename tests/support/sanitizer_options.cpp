// Linked into every sanitized executable (cmake/sanitized.cmake): the test suites' copies and the
// server and agent the integration tests start. The sanitizers read these defaults before main,
// so a test needs no environment; ASAN_OPTIONS and UBSAN_OPTIONS still override them.

extern "C" {

// A leak fails the program (LeakSanitizer runs at exit); a bad access aborts at once with its
// stack; stack memory is checked after return and after its scope as well.
const char* __asan_default_options() {
  return "abort_on_error=1:detect_leaks=1:detect_stack_use_after_return=1:"
         "check_initialization_order=1:strict_init_order=1";
}

// Undefined behaviour is an error, reported with its stack (the build adds
// -fno-sanitize-recover=undefined, so it also stops the program).
const char* __ubsan_default_options() {
  return "print_stacktrace=1:halt_on_error=1";
}

// Mesa unloads its driver when the renderer's EGL display is terminated, and memory the driver
// still holds in its own globals then looks leaked: LeakSanitizer no longer sees those globals
// and cannot even name the module (it reported 128 bytes from "<unknown module>" in every test
// that renders). Keeping every library loaded until exit keeps its globals in view, so only real
// leaks are reported. Nothing in these programs depends on a library being unloaded.
int dlclose(void*) noexcept {
  return 0;
}

}  // extern "C"
