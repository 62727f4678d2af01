/*
** Display values and linear light (display.h).
*/
#include "display.h"

#include <math.h>
#include <pthread.h>

static float srgb_to_linear(float c) {
  if (c <= 0) return 0;
  if (c >= 1) return c == 1 ? 1 : powf(c, 2.4f);   /* > 1 stays monotone */
  return c <= 0.04045f ? c / 12.92f : powf((c + 0.055f) / 1.055f, 2.4f);
}

#define SRGB_LUT 4096
static float srgb_lut[SRGB_LUT + 2];
static pthread_once_t lut_once = PTHREAD_ONCE_INIT;

static void lut_init(void) {
  for (int i = 0; i <= SRGB_LUT; i++) srgb_lut[i] = srgb_to_linear((float)i / SRGB_LUT);
  srgb_lut[SRGB_LUT + 1] = 1;
}

float display_to_linear(float c) {
  if (!(c > 0)) return 0;
  if (c >= 1) return srgb_to_linear(c);
  pthread_once(&lut_once, lut_init);
  float x = c * SRGB_LUT;
  int i = (int)x;
  return srgb_lut[i] + (x - (float)i) * (srgb_lut[i + 1] - srgb_lut[i]);
}

float display_from_linear(float c) {
  if (!(c > 0)) return 0;
  if (c >= 1) return 1;
  return c <= 0.0031308f ? c * 12.92f : 1.055f * powf(c, 1 / 2.4f) - 0.055f;
}
