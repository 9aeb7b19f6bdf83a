#pragma once
// ARDCELL_TEST_ASAN: 1 in a build with AddressSanitizer (GCC's __SANITIZE_ADDRESS__ or Clang's
// __has_feature), else 0; for tests that size their work or read the sanitizer's allocator.
#if defined(__SANITIZE_ADDRESS__)
#define ARDCELL_TEST_ASAN 1
#elif defined(__has_feature)
#if __has_feature(address_sanitizer)
#define ARDCELL_TEST_ASAN 1
#endif
#endif
#ifndef ARDCELL_TEST_ASAN
#define ARDCELL_TEST_ASAN 0
#endif
