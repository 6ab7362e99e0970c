"""Acceptance tests for EXQVFL, the Queen Victoria edge extractor (nstar/exqvfl.py).

Every expected feature list below was worked out by hand from the EXQVFL.FR
listing (Appendix F), with the OCR repairs of QUIRKS Q1-Q3 (JLCC/ILCC -> JLOC/
ILOC, LABS -> IABS, Sl -> S1, 1PIX -> IPIX, label 200 block =
``INUM=ILOC-JLOC+1; IF (INUM .GT. 3) GOTO 220``).  The listing, repaired, is
copied here so the traces can be checked against it:

    JLOC=1; IPRE=1; NFEAT=0; NFMAX=50
100 ILOC=IPRE; IVLE=IPIX(ILOC); IPRE=ILOC+1; IF (IPRE.GT.ILAST) GOTO 300
    IVRE=IPIX(IPRE); ICHG=IVRE-IVLE; ISLP=ISGN(ICHG); IF (ISLP.EQ.0) GOTO 100
    INEXT=IPRE; IF (IABS(ICHG).GT.ITHR) GOTO 120
    IPASS=0; IVPRE=IVRE
110 INEXT=INEXT+1; IF (INEXT.GT.ILAST) GOTO 300
    IVRE=IPIX(INEXT); IDIFF=IVRE-IVPRE
    IF (ISGN(IDIFF).EQ.ISLP) GOTO 120; IF (IDIFF.NE.0) GOTO 100
    IF (IPASS.EQ.1) GOTO 100; IPASS=1; GOTO 110
120 ICHG=IVRE-IVLE; IVPRE=IVRE; IPRE=INEXT; INEXT=INEXT+1
    IF (INEXT.GT.ILAST) GOTO 200
    IVRE=IPIX(INEXT); IDIFF=IVRE-IVPRE; IF (ISGN(IDIFF).EQ.ISLP) GOTO 120
    IF (IABS(IDIFF).GT.ITHR) GOTO 200
    INEXT=INEXT+1; IF (INEXT.GT.ILAST) GOTO 200
    IVRE=IPIX(INEXT); IDIFF=IVRE-IVPRE; IF (ISGN(IDIFF).EQ.ISLP) GOTO 120
    GOTO 200
200 INUM=ILOC-JLOC+1; IF (INUM.GT.3) GOTO 220
    ISUM=IPIX(JLOC)+...+IPIX(ILOC); SUM=ISUM; IVAVE=(SUM/INUM)+.5; IV1=IVAVE
    GOTO 240
220 IS1=IPIX(JLOC)+IPIX(JLOC+1)+IPIX(JLOC+2); IS2=IPIX(ILOC)+IPIX(ILOC-1)+IPIX(ILOC-2)
    IVAVE=(S1/3.0)+.5; IV1=(S2/3.0)+.5
240 IF (NFEAT.GE.NFMAX) GOTO 500
    NFEAT=NFEAT+1; IFEAT(NFEAT,1..4)=ILOC,IPRE,IV1,IVPRE
    IF (NFEAT.GT.1) IFEAT(NFEAT-1,4)=IVAVE
    IF (INEXT.GT.ILAST) GOTO 300; INEXT=IPRE; JLOC=IPRE; GOTO 100
300 IF (NFEAT.LE.0) RETURN; IF (INUM.GE.1) GOTO 400
    IFEAT(NFEAT,4)=IPIX(ILAST); GOTO 410
400 sum IPIX(JLOC+K) for K=0..2 with JLOC+K.LE.ILOC -> ISUM, INUM
    IFEAT(NFEAT,4)=(SUM/INUM)+.5
410 IFLOC=1; DO 490 ILOC=2,NFEAT
      IF (IFEAT(IFLOC,2).LT.IFEAT(ILOC,1)) GOTO 430
      IF (width(ILOC).GT.1 .OR. width(IFLOC).GT.1) GOTO 430
      IFEAT(IFLOC,2)=IFEAT(ILOC,2); IFEAT(IFLOC,4)=IFEAT(ILOC,4); GOTO 490
430   IFLOC=IFLOC+1; IFEAT(IFLOC,.)=IFEAT(ILOC,.)
490 CONTINUE; NFEAT=IFLOC; RETURN
500 TYPE "-- EXIDEG -- TOO MANY FEATURES."; RETURN

Notation in the traces: p(k) is IPIX(k), 1-based; "mean3(a,b,c)" is
int((a+b+c)/3 + .5) in DG REAL arithmetic (for 4-bit grey levels the
truncation never lands on a boundary, so it equals sum/n rounded half up).
Feature tuples are (start, stop, left grey, right grey) = IFEAT(k,1..4).
NSTAR calls EXQVFL with ITHR=2 for slices, RADSP with ITHR=1 for rays.
"""


from nstar.exqvfl import exqvfl, feature_list


def run(row, thr, **kw):
    n, ifeat = exqvfl(row, thr, **kw)
    return feature_list(n, ifeat)


def test_flat_row_has_no_features():
    # 100 with ICHG=0 loops ILOC=1..9; ILOC=10 -> IPRE=11 > ILAST -> 300,
    # NFEAT=0 -> RETURN.
    assert run([5] * 10, 2) == []
    assert run([0] * 128, 1) == []


def test_single_pixel_row():
    # ILOC=1, IPRE=2 > ILAST=1 -> 300 -> NFEAT=0.
    assert run([7], 2) == []


def test_single_step():
    # p = 2 2 2 2 9 9 9 9, ITHR=2
    # 100: ILOC=1..3 flat.  ILOC=4 (2), IPRE=5 (9): ICHG=7 > 2 -> INEXT=5 -> 120.
    # 120: IVPRE=9, IPRE=5, INEXT=6 (9): IDIFF=0, not > 2 -> INEXT=7 (9): IDIFF=0,
    #      not the slope -> 200.
    # 200: INUM=4-1+1=4 > 3 -> 220: IS1=p1+p2+p3=6 -> IVAVE=2; IS2=p4+p3+p2=6 -> IV1=2.
    #      F1=(4,5,2,9).  INEXT=7 <= 8 -> INEXT=5, JLOC=5 -> 100.
    # 100: ILOC=5..7 flat; ILOC=8, IPRE=9 > 8 -> 300.
    # 400: JLOC=5, ILOC=8: p5+p6+p7=27 -> 9 -> F1 right grey 9.
    assert run([2, 2, 2, 2, 9, 9, 9, 9], 2) == [(4, 5, 2, 9)]


def test_down_step_with_short_left_run_rounds_half_up():
    # p = 4 3 12 12 12, ITHR=2
    # 100: ILOC=1 (4), IPRE=2 (3): ICHG=-1, gentle: INEXT=2, IPASS=0, IVPRE=3.
    # 110: INEXT=3 (12): IDIFF=+9, sign != -1, non-zero -> 100.
    # 100: ILOC=2 (3), IPRE=3 (12): ICHG=9 > 2 -> 120.
    # 120: IVPRE=12, IPRE=3, INEXT=4 (12) flat -> INEXT=5 (12) flat -> 200.
    # 200: INUM=2-1+1=2 <= 3: ISUM=p1+p2=7, 7/2+.5 = 4.0 -> IV1=IVAVE=4
    #      (the left grey is 4 although the pixel beside the edge is 3).
    #      F1=(2,3,4,12); INEXT=5 <= 5 -> JLOC=3 -> 100 ... ILOC=5 -> 300.
    # 400: JLOC=3, ILOC=5: p3+p4+p5=36 -> 12.
    assert run([4, 3, 12, 12, 12], 2) == [(2, 3, 4, 12)]


def test_ramp():
    # p = 1 1 1 1 4 7 10 13 13 13 13, ITHR=2
    # 100: ILOC=1..3 flat; ILOC=4 (1), IPRE=5 (4): +3 > 2 -> 120.
    # 120: IPRE=5, p6=7 same sign -> 120: IPRE=6, p7=10 -> 120: IPRE=7, p8=13 -> 120:
    #      IVPRE=13, IPRE=8, p9=13 flat -> lookahead p10=13 flat -> 200.
    # 200: INUM=4 -> IS1=3 -> IVAVE=1, IS2=p4+p3+p2=3 -> IV1=1. F1=(4,8,1,13).
    #      INEXT=10 <= 11 -> JLOC=8 -> 100 flat ... ILOC=11 -> 300.
    # 400: JLOC=8: p8+p9+p10=39 -> 13.
    assert run([1, 1, 1, 1, 4, 7, 10, 13, 13, 13, 13], 2) == [(4, 8, 1, 13)]


def test_noise_spike_below_threshold_vs_threshold_1():
    row = [5, 5, 5, 5, 7, 5, 5, 5, 5]
    # ITHR=2:
    # 100: ILOC=4 (5), IPRE=5 (7): +2, not > 2: gentle, IVPRE=7.
    # 110: INEXT=6 (5): IDIFF=-2, not the slope, non-zero -> 100.
    # 100: ILOC=5 (7), IPRE=6 (5): -2 gentle, IVPRE=5.
    # 110: INEXT=7 flat -> IPASS=1; INEXT=8 flat, IPASS=1 -> 100.
    # 100: ILOC=6..8 flat; ILOC=9 -> 300; NFEAT=0 -> no features.
    assert run(row, 2) == []
    # ITHR=1:
    # 100: ILOC=4 (5), IPRE=5 (7): +2 > 1 -> 120: IVPRE=7, IPRE=5, p6=5: IDIFF=-2,
    #      |-2| > 1 -> 200: INUM=4 -> IS1=15 -> 5, IS2=15 -> 5. F1=(4,5,5,7).
    #      INEXT=6 <= 9 -> INEXT=5, JLOC=5 -> 100.
    # 100: ILOC=5 (7), IPRE=6 (5): -2 > 1 -> 120: IVPRE=5, IPRE=6, p7 flat ->
    #      lookahead p8 flat -> 200: INUM=5-5+1=1: ISUM=p5=7 -> 7.5 -> 7.
    #      F2=(5,6,7,5); F1 right grey = IVAVE = 7.  JLOC=6 -> 100 ... -> 300.
    # 400: JLOC=6, ILOC=9: p6+p7+p8=15 -> 5: F2=(5,6,7,5).
    # 410: F1 stop 5 is not < F2 start 5; widths 1 and 1 -> combine:
    #      F1=(4,6,5,5), NFEAT=1.
    assert run(row, 1) == [(4, 6, 5, 5)]


def test_narrow_up_down_spike_is_merged():
    # p = 3 3 3 3 10 3 3 3, ITHR=2
    # 100: ILOC=4 (3), IPRE=5 (10): +7 -> 120: IVPRE=10, IPRE=5, p6=3: -7 > 2 -> 200.
    # 200: INUM=4 -> IS1=9 -> 3, IS2=9 -> 3. F1=(4,5,3,10). JLOC=5 -> 100.
    # 100: ILOC=5 (10), IPRE=6 (3): -7 -> 120: IVPRE=3, IPRE=6, p7, p8 flat -> 200.
    # 200: INUM=1: ISUM=10 -> 10.5 -> 10. F2=(5,6,10,3); F1 right grey=10.
    #      INEXT=8 <= 8 -> JLOC=6 -> 100 ... ILOC=8 -> 300.
    # 400: JLOC=6: p6+p7+p8=9 -> 3. F2=(5,6,10,3).
    # 410: 5 not < 5, widths 1 and 1 -> F1=(4,6,3,3).
    n, ifeat = exqvfl([3, 3, 3, 3, 10, 3, 3, 3], 2)
    assert feature_list(n, ifeat) == [(4, 6, 3, 3)]
    # The merge does not clear row 2: IFEAT(2,.) still holds F2 (this is what
    # NSTAR writes to SLICE.DT past NFEAT).
    assert tuple(ifeat[j][1] for j in range(4)) == (5, 6, 10, 3)


def test_two_pixel_wide_spike_is_not_merged():
    # p = 3 3 3 3 10 10 3 3 3, ITHR=2
    # 100: ILOC=4 (3), IPRE=5 (10) -> 120: IVPRE=10, IPRE=5, p6=10 flat ->
    #      lookahead p7=3: IDIFF=-7, not the slope -> 200 (INEXT=7).
    # 200: INUM=4 -> 3, 3. F1=(4,5,3,10). JLOC=5, INEXT=5 -> 100.
    # 100: ILOC=5 (10), IPRE=6 (10) flat; ILOC=6 (10), IPRE=7 (3): -7 -> 120:
    #      IVPRE=3, IPRE=7, p8, p9 flat -> 200: INUM=6-5+1=2: ISUM=20 -> 10.
    #      F2=(6,7,10,3); F1 right grey=10. JLOC=7 -> ... -> 300.
    # 400: JLOC=7: p7+p8+p9=9 -> 3.
    # 410: F1 stop 5 < F2 start 6 -> kept apart.
    assert run([3, 3, 3, 3, 10, 10, 3, 3, 3], 2) == [(4, 5, 3, 10), (6, 7, 10, 3)]


def test_two_adjacent_edges_not_merged_when_one_is_wide():
    # p = 2 2 2 2 6 10 3 3 3, ITHR=2
    # 100: ILOC=4 (2), IPRE=5 (6): +4 -> 120: IPRE=5, p6=10 same sign -> 120:
    #      IVPRE=10, IPRE=6, p7=3: -7 > 2 -> 200.
    # 200: INUM=4 -> IS1=6 -> 2, IS2=p4+p3+p2=6 -> 2. F1=(4,6,2,10). JLOC=6 -> 100.
    # 100: ILOC=6 (10), IPRE=7 (3): -7 -> 120: IVPRE=3, IPRE=7, p8, p9 flat -> 200.
    # 200: INUM=6-6+1=1: ISUM=10 -> 10. F2=(6,7,10,3); F1 right grey=10.
    # 400: JLOC=7: p7+p8+p9=9 -> 3.
    # 410: F1 stop 6 is not < F2 start 6, but IWD2 = 6-4 = 2 > 1 -> kept apart.
    assert run([2, 2, 2, 2, 6, 10, 3, 3, 3], 2) == [(4, 6, 2, 10), (6, 7, 10, 3)]


def test_edges_at_both_ends():
    # p = 1 8 8 8 8 8 8 2, ITHR=2
    # 100: ILOC=1 (1), IPRE=2 (8): +7 -> 120: IVPRE=8, IPRE=2, p3, p4 flat -> 200.
    # 200: INUM=1-1+1=1: ISUM=p1=1 -> 1.5 -> 1. F1=(1,2,1,8). INEXT=4 <= 8 ->
    #      INEXT=2, JLOC=2 -> 100.
    # 100: ILOC=2..6 flat; ILOC=7 (8), IPRE=8 (2): -6 -> INEXT=8 -> 120:
    #      IVPRE=2, IPRE=8, INEXT=9 > 8 -> 200.
    # 200: INUM=7-2+1=6 > 3: IS1=p2+p3+p4=24 -> 8, IS2=p7+p6+p5=24 -> 8.
    #      F2=(7,8,8,2); F1 right grey=8.  INEXT=9 > ILAST -> 300 (JLOC stays 2!).
    # 300: INUM=6 >= 1 -> 400: JLOC=2, ILOC=7: p2+p3+p4=24 -> 8 -> F2 right grey=8.
    #      (Quirk Q6: the last feature's right grey is the mean of the run
    #      *before* it, not the 2 at the end of the row -- kept, genuine listing.)
    # 410: F1 stop 2 < F2 start 7 -> kept apart.
    assert run([1, 8, 8, 8, 8, 8, 8, 2], 2) == [(1, 2, 1, 8), (7, 8, 8, 8)]


def test_feature_ending_in_a_lookahead_past_the_end():
    # p = 2 2 2 9 8, ITHR=2
    # 100: ILOC=3 (2), IPRE=4 (9): +7 -> 120: IVPRE=9, IPRE=4, p5=8: IDIFF=-1,
    #      |-1| <= 2 -> INEXT=6 > 5 -> 200.
    # 200: INUM=3 <= 3: ISUM=6 -> 2.5 -> 2. F1=(3,4,2,9). INEXT=6 > 5 -> 300.
    # 400: JLOC=1 (not advanced), ILOC=3: p1+p2+p3=6 -> 2: right grey 2 (Q6 again).
    assert run([2, 2, 2, 9, 8], 2) == [(3, 4, 2, 2)]


def test_ilast_argument_limits_the_scan():
    # Same row as test_edges_at_both_ends with ILAST=7: the down step at p8 is
    # never seen.  F1=(1,2,1,8) as before; then 100 flat from ILOC=2 to ILOC=7,
    # IPRE=8 > 7 -> 300 -> 400: JLOC=2, ILOC=7: p2+p3+p4=24 -> 8.
    assert run([1, 8, 8, 8, 8, 8, 8, 2], 2, ilast=7) == [(1, 2, 1, 8)]


def test_gentle_slope_confirmed_by_second_step():
    # p = 5 5 5 6 7 7 7 7, ITHR=2
    # 100: ILOC=3 (5), IPRE=4 (6): +1 gentle, IPASS=0, IVPRE=6.
    # 110: INEXT=5 (7): IDIFF=+1 = ISLP -> 120: IVPRE=7, IPRE=5, p6, p7 flat -> 200.
    # 200: INUM=3-1+1=3 <= 3: ISUM=15 -> 5.5 -> 5. F1=(3,5,5,7). JLOC=5 ... -> 300.
    # 400: JLOC=5: p5+p6+p7=21 -> 7.
    assert run([5, 5, 5, 6, 7, 7, 7, 7], 2) == [(3, 5, 5, 7)]


def test_gentle_slope_with_one_flat_pixel():
    # p = 5 5 5 6 6 7 7 7 7, ITHR=2
    # 100: ILOC=3 (5), IPRE=4 (6): +1 gentle, IVPRE=6.
    # 110: INEXT=5 (6): IDIFF=0, IPASS=0 -> IPASS=1 -> 110: INEXT=6 (7): +1 -> 120.
    # 120: IVPRE=7, IPRE=6, p7, p8 flat -> 200: INUM=3: ISUM=15 -> 5. F1=(3,6,5,7).
    # 400: JLOC=6: p6+p7+p8=21 -> 7.
    assert run([5, 5, 5, 6, 6, 7, 7, 7, 7], 2) == [(3, 6, 5, 7)]


def test_gentle_slope_with_two_flat_pixels_is_not_a_feature():
    # p = 5 5 5 6 6 6 7 7 7, ITHR=2
    # 100: ILOC=3 (5), IPRE=4 (6): gentle.  110: p5 flat -> IPASS=1; p6 flat with
    #      IPASS=1 -> 100.  ILOC=4, 5 flat; ILOC=6 (6), IPRE=7 (7): gentle;
    #      110: p8 flat -> IPASS=1; p9 flat -> 100; ILOC=7, 8 flat; ILOC=9 -> 300.
    # NFEAT=0.
    assert run([5, 5, 5, 6, 6, 6, 7, 7, 7], 2) == []
    # With ITHR=0 every step is steep: ILOC=3 -> 120: p5 flat, lookahead p6 flat
    # -> 200: INUM=3, ISUM=15 -> 5: F1=(3,4,5,6); JLOC=4; 100: ILOC=4,5 flat;
    # ILOC=6 (6), IPRE=7 (7) -> 120: p8, p9 flat -> 200: INUM=6-4+1=3:
    # ISUM=18 -> 6.5 -> 6: F2=(6,7,6,7), F1 right grey 6; INEXT=9 <= 9 -> JLOC=7
    # -> ... -> 400: JLOC=7: p7+p8+p9=21 -> 7.  410: 4 < 6 -> apart.
    assert run([5, 5, 5, 6, 6, 6, 7, 7, 7], 0) == [(3, 4, 5, 6), (6, 7, 6, 7)]


def test_gentle_start_is_absorbed_into_a_steep_edge():
    # p = 3 4 12 12 12, ITHR=2
    # 100: ILOC=1 (3), IPRE=2 (4): +1 gentle.  110: INEXT=3 (12): +8 = ISLP -> 120
    #      with ILOC still 1: IVPRE=12, IPRE=3, p4, p5 flat -> 200.
    # 200: INUM=1: ISUM=3 -> 3.5 -> 3. F1=(1,3,3,12).  400: JLOC=3: 36 -> 12.
    assert run([3, 4, 12, 12, 12], 2) == [(1, 3, 3, 12)]


def test_slope_survives_one_small_opposite_step():
    # p = 2 2 2 5 4 8 8 8 8, ITHR=2
    # 100: ILOC=3 (2), IPRE=4 (5): +3 -> 120: IVPRE=5, IPRE=4, p5=4: IDIFF=-1,
    #      |-1| <= 2 -> INEXT=6 (8): IDIFF=8-5=+3 = ISLP -> 120: IVPRE=8, IPRE=6,
    #      p7, p8 flat -> 200.
    # 200: INUM=3: ISUM=6 -> 2.5 -> 2. F1=(3,6,2,8).  400: JLOC=6: 24 -> 8.
    assert run([2, 2, 2, 5, 4, 8, 8, 8, 8], 2) == [(3, 6, 2, 8)]


def test_long_flat_run_greys_are_means_of_three_nearest():
    # p = 4 4 4 4 4 5 5 4 12 10 11 11 11 11, ITHR=2
    # 100: ILOC=1..4 flat. ILOC=5 (4), IPRE=6 (5): +1 gentle, IVPRE=5.
    # 110: p7=5 flat -> IPASS=1; p8=4: IDIFF=-1 -> 100.
    # 100: ILOC=6 (5), IPRE=7 (5) flat; ILOC=7 (5), IPRE=8 (4): -1 gentle, IVPRE=4.
    # 110: p9=12: IDIFF=+8, not -1 -> 100.
    # 100: ILOC=8 (4), IPRE=9 (12): +8 -> 120: IVPRE=12, IPRE=9, p10=10: IDIFF=-2,
    #      not > 2 -> lookahead p11=11: IDIFF=11-12=-1, not +1 -> 200.
    # 200: INUM=8-1+1=8 > 3: IS1=p1+p2+p3=12 -> 4.5 -> 4 (IVAVE, unused: NFEAT=1);
    #      IS2=p8+p7+p6=4+5+5=14 -> 4.666+.5=5.166 -> IV1=5.  F1=(8,9,5,12).
    #      INEXT=11 <= 14 -> INEXT=9, JLOC=9 -> 100.
    # 100: ILOC=9 (12), IPRE=10 (10): -2 gentle; 110: p11=11: +1 -> 100.
    #      ILOC=10 (10), IPRE=11 (11): +1 gentle; 110: p12 flat, p13 flat -> 100.
    #      ILOC=11..13 flat; ILOC=14 -> 300.
    # 400: JLOC=9, ILOC=14: p9+p10+p11=12+10+11=33 -> 11.5 -> 11.
    row = [4, 4, 4, 4, 4, 5, 5, 4, 12, 10, 11, 11, 11, 11]
    assert run(row, 2) == [(8, 9, 5, 11)]


def _spikes(n):
    # period 4: 0 0 8 0, a 1-pixel spike at p(4j+3)
    return [0, 0, 8, 0] * n


def test_more_than_50_features_returns_50_unmerged():
    # p = (0 0 8 0) x 30, ITHR=2.  Per spike j (0-based, spike at p(4j+3)):
    #   from ILOC=4j+2 (0), IPRE=4j+3 (8): +8 -> 120: p(4j+4)=0: -8 > 2 -> 200:
    #     the run before is p(JLOC..4j+2), all 0 -> IV1=0: (4j+2, 4j+3, 0, 8).
    #   JLOC=4j+3; 100: ILOC=4j+3 (8), IPRE=4j+4 (0): -8 -> 120: two flat
    #     pixels -> 200: INUM=1, ISUM=8 -> IV1=IVAVE=8: (4j+3, 4j+4, 8, 0),
    #     and the up-edge's right grey becomes 8.
    #   The next up-edge's IVAVE (mean of p(4j+4..4j+6) = 0) sets the
    #   down-edge's right grey to 0.
    # 30 spikes give 60 raw features; the 51st (j=25 up-edge) hits
    # 240: NFEAT >= NFMAX -> 500: TYPE the message, RETURN with NFEAT=50 and no
    # merge (quirk Q7).  The 50th (j=24 down-edge, (99,100,8,0)) keeps IVPRE=0.
    msgs = []
    n, ifeat = exqvfl(_spikes(30), 2, warn=msgs.append)
    assert n == 50
    expected = []
    for j in range(25):
        expected += [(4 * j + 2, 4 * j + 3, 0, 8), (4 * j + 3, 4 * j + 4, 8, 0)]
    assert feature_list(n, ifeat) == expected
    assert msgs == ["-- EXIDEG -- TOO MANY FEATURES."]


def test_exactly_50_raw_features_are_merged():
    # p = (0 0 8 0) x 25: 50 raw features as above, the 50th (99,100) stored
    # from 120 with INEXT=101 > 100 -> 300 with JLOC=99, ILOC=99:
    # 400: p99=8 only -> right grey 8 (Q6).  No 51st feature, so 410 runs:
    # each touching pair of width-1 features merges to (4j+2, 4j+4, 0, 0),
    # the last to (98, 100, 0, 8).  NFEAT=25.
    msgs = []
    got = run(_spikes(25), 2, warn=msgs.append)
    assert got == [(4 * j + 2, 4 * j + 4, 0, 0) for j in range(24)] + [(98, 100, 0, 8)]
    assert msgs == []


def test_ifeat_table_updated_in_place_and_rows_past_nfeat_kept():
    # A caller's table (NSTAR's IFBUF) with old values: rows past the raw
    # feature count keep them.  Row [2,2,2,2,9,9,9,9] gives one feature (see
    # test_single_step), written into row 1 only.
    table = [[77] * 50 for _ in range(4)]
    n, ifeat = exqvfl([2, 2, 2, 2, 9, 9, 9, 9], 2, ifeat=table)
    assert ifeat is table
    assert n == 1
    assert [col[0] for col in table] == [4, 5, 2, 9]
    assert all(col[k] == 77 for col in table for k in range(1, 50))


def test_threshold_boundary_is_strictly_greater():
    # |step| = ITHR is gentle (IABS(ICHG).GT.ITHR is false), |step| = ITHR+1 is
    # steep.  p = 6 6 6 8 8 8, one step of +2:
    #   ITHR=2: gentle; 110: p5 flat -> IPASS=1; p6 flat -> 100; rest flat -> none.
    #   ITHR=1: steep -> 120: p5, p6 flat -> 200: INUM=3: ISUM=18 -> 6.5 -> 6.
    #           F1=(3,4,6,8); INEXT=6 <= 6 -> JLOC=4 ... 400: p4+p5+p6=24 -> 8.
    row = [6, 6, 6, 8, 8, 8]
    assert run(row, 2) == []
    assert run(row, 1) == [(3, 4, 6, 8)]
