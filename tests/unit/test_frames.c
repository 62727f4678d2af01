/*
** Animation frames (sumi render --frames A:B [--loop]): the clock each frame
** sees. Without --loop it runs 0..1 from the first frame to the last; with
** it, a loop of n frames takes clock k / n, so the last frame is not the
** first again and frame n would be (clock 1 = clock 0 of the next turn).
*/
#include "../../src/scene/scene.h"
#include "unit.h"

TEST(frames_run_from_0_to_1) {
  CHECK_NEAR(scene_frame_clock(0, 11, 0, 0), 0, 0);
  CHECK_NEAR(scene_frame_clock(0, 11, 11, 0), 1, 0);
  CHECK_NEAR(scene_frame_clock(0, 11, 3, 0), 3.0 / 11, 1e-15);
  CHECK_NEAR(scene_frame_clock(5, 9, 7, 0), 0.5, 1e-15);
  CHECK_NEAR(scene_frame_clock(4, 4, 4, 0), 0, 0);   /* one frame */
}

TEST(loop_stays_below_1) {
  /* 12 frames, 0..11: clock k / 12, the last 11 / 12, and the turn's
  ** 13th frame would be clock 1, where the loop starts over */
  for (int k = 0; k < 12; k++) CHECK_NEAR(scene_frame_clock(0, 11, k, 1), k / 12.0, 1e-15);
  CHECK(scene_frame_clock(0, 11, 11, 1) < 1);
  CHECK_NEAR(scene_frame_clock(0, 11, 12, 1), 1, 0);
  CHECK_NEAR(scene_frame_clock(10, 13, 12, 1), 0.5, 1e-15);   /* 4 frames from 10 */
  CHECK_NEAR(scene_frame_clock(4, 4, 4, 1), 0, 0);            /* one frame: still 0 */
}

int main(void) {
  RUN(frames_run_from_0_to_1);
  RUN(loop_stays_below_1);
  return unit_done();
}
