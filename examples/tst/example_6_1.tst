# Example 6.1 / 6.2 of the HDRC3 chapter (section 6.3): two RMAXes concurrently scan the areas
# AreaA and AreaB, after which the first one flies to Dest4. The world is revinge
# (sim/worlds/revinge.toml); areas are in its local frame (metres east, north of the origin).
world revinge
agents uav0, uav1

# The open fields west of the town: AreaA north of the track to the pads, AreaB south of it.
area AreaA = polygon((-280, -40), (-160, -40), (-160, 40), (-280, 40))
area AreaB = polygon((-180, -120), (-80, -120), (-80, -60), (-180, -60))
# Dest4: 40 m above the town square.
point Dest4 = town_square at 40

tau0(P0, TS0, TE0) = with TS1, TE1, TS4, TE4 sequence
  tau1(TS1, TE1) = with TS2, TE2, P3, TS3, TE3 concurrent
    tau2(TS2, TE2) = scan-area(TS2, TE2, Speed2, AreaA);
    tau3(P3, TS3, TE3) = scan-area(TS3, TE3, Speed3, AreaB)
  where cons_tau1 and P3 = uav1;
  tau4(TS4, TE4) = fly-to(TS4, TE4, Speed4, Dest4)
where cons_tau0 and P0 = uav0 and TE0 <= 1200

cons_tau0 = TS0 <= TS1 and TS1 < TE1 and TE1 <= TS4 and TS4 < TE4 and TE4 <= TE0
cons_tau1 = TS1 <= TS2 and TS2 < TE2 and TE2 <= TE1 and TS1 <= TS3 and TS3 < TE3 and TE3 <= TE1
