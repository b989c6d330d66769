# Mission leg I of the emergency-services scenario (chapter section 11.1.1): two RMAXes take
# off from H1 and H2, each scans its half of the operator's rectangle (band 1 and band 2 of 2,
# planned apart and agreeing on the split) with the cameras straight down and the PPC's saliency
# pipeline running, then flies back over its pad and lands. The output is the saliency map:
# one per aircraft on /<agent>/saliency/map (GeoJSON). Run it with cameras:
#   hdrc3 tst run examples/tst/leg1_scan.tst --launch --agents uav0,uav1 --speed 1
world revinge
agents uav0, uav1

# The operator's rectangle: the fields south-west of the town (bodies 03 and 04 lie in it).
area Region = polygon((-180, -180), (-80, -180), (-80, -50), (-180, -50))
point OverH1 = H1 at 20
point OverH2 = H2 at 20

leg1(P0, TS0, TE0) = with P1, TS1, TE1, P2, TS2, TE2 concurrent
  west(P1, TS1, TE1) = with T1, T2, T3, T4, T5, T6 sequence
    scan1(T1, T2) = scan-area(T1, T2, 5, Region, 30, 1, 2);
    home1(T3, T4) = fly-to(T3, T4, 6, OverH1);
    land1(T5, T6) = land(T5, T6, 0)
  where P1 = uav0;
  east(P2, TS2, TE2) = with U1, U2, U3, U4, U5, U6 sequence
    scan2(U1, U2) = scan-area(U1, U2, 5, Region, 30, 2, 2);
    home2(U3, U4) = fly-to(U3, U4, 6, OverH2);
    land2(U5, U6) = land(U5, U6, 0)
  where P2 = uav1
where P0 = uav0 and TS0 = 0 and TE0 <= 1500
