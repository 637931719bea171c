// OpenCV 4.6's EdgeDrawing (ximgproc, used by the line detectors) leaks ~32 bytes per detector
// object inside the library. Under the sanitizer build LeakSanitizer would fail every run of the
// program on it; this suppresses exactly that module (our own leaks are still reported) and keeps
// the suppression statistics out of the program's output. Only read by LeakSanitizer; unused
// functions otherwise.
extern "C" const char* __lsan_default_suppressions() { return "leak:libopencv_ximgproc\n"; }
extern "C" const char* __lsan_default_options() { return "print_suppressions=0"; }
