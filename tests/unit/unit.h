/*
** A tiny unit-test harness: each TEST is a function; CHECK records a
** failure with file:line and carries on. The binary ends with the line
** "N passed, N failed" (one count per TEST) that tests/run.sh adds up.
**
**   TEST(bezier_corners) { CHECK_NEAR(p.x, 1.0, 1e-12); }
**   int main(void) { RUN(bezier_corners); return unit_done(); }
*/
#ifndef tests_unit_h
#define tests_unit_h

#include <math.h>
#include <stdio.h>

static int unit_failed_checks, unit_passed, unit_failed;
static const char *unit_current;

#define TEST(name) static void test_##name(void)
#define RUN(name) unit_run(test_##name, #name)

#define CHECK(cond) \
  do { if (!(cond)) unit_fail(__FILE__, __LINE__, "CHECK(" #cond ")"); } while (0)
#define CHECK_NEAR(a, b, eps) \
  do { double a_ = (a), b_ = (b); \
       if (!(fabs(a_ - b_) <= (eps))) { \
         char m_[256]; snprintf(m_, sizeof m_, "%s = %.17g, expected %.17g (+-%g)", #a, a_, b_, (double)(eps)); \
         unit_fail(__FILE__, __LINE__, m_); } } while (0)
#define CHECK_EQ_INT(a, b) \
  do { long long a_ = (long long)(a), b_ = (long long)(b); \
       if (a_ != b_) { char m_[256]; snprintf(m_, sizeof m_, "%s = %lld, expected %lld", #a, a_, b_); \
         unit_fail(__FILE__, __LINE__, m_); } } while (0)

static void unit_fail(const char *file, int line, const char *msg) {
  fprintf(stderr, "%s:%d: in %s: %s\n", file, line, unit_current, msg);
  unit_failed_checks++;
}

static void unit_run(void (*fn)(void), const char *name) {
  int before = unit_failed_checks;
  unit_current = name;
  fn();
  if (unit_failed_checks == before) unit_passed++;
  else { unit_failed++; fprintf(stderr, "FAIL %s\n", name); }
}

static int unit_done(void) {
  printf("%d passed, %d failed\n", unit_passed, unit_failed);
  return unit_failed != 0;
}

#endif
