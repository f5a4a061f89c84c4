/* refusal_check.h: what the C tests of the C interface's refusals check alike (test_errors.c, test_plan.c): a
 * failure count, expect(), and a creation that must be refused with its documented code, no handle written
 * and a message naming what was wrong. Each test is one C99 file that includes this once. */
#ifndef CONTACTNN_TESTS_CAPI_REFUSAL_CHECK_H
#define CONTACTNN_TESTS_CAPI_REFUSAL_CHECK_H

#include <contactnn/contactnn.h>
#include <stdio.h>
#include <string.h>

static int failures = 0;

static void expect(int condition, const char* what) {
  if (!condition) {
    printf("FAIL: %s\n", what);
    ++failures;
  }
}

/* A creation that returned `result` and left `search`: it must return `code`, write no handle and leave a
 * message containing `needle`. */
static void expect_refusal(int result, const contactnn_search* search, int code, const char* needle,
                           const char* what) {
  printf("%-44s -> %d: %s\n", what, result, contactnn_last_error());
  if (result != code) {
    printf("FAIL: %s: returned %d, expected %d\n", what, result, code);
    ++failures;
  }
  if (search != NULL) {
    printf("FAIL: %s: a handle was written\n", what);
    ++failures;
  }
  if (strstr(contactnn_last_error(), needle) == NULL) {
    printf("FAIL: %s: the message does not name '%s'\n", what, needle);
    ++failures;
  }
}

#endif
