# Example 6.2 of the HDRC3 chapter (section 6.3.2) as written there, in ASCII: the TST of
# Figure 15(b) with the named constraint sets cons_tau0 and cons_tau1. Only the values it names
# are declared; agents are left open (P of tau0 is an open parameter that `hdrc3 tst set` or the
# delegation may fix).
world revinge
area AreaA = polygon((-280, -40), (-160, -40), (-160, 40), (-280, 40))
area AreaB = polygon((-180, -120), (-80, -120), (-80, -60), (-180, -60))
point Dest4 = town_square at 40

tau0(TS0, TE0) = with TS1, TE1, TS4, TE4 sequence
  tau1(TS1, TE1) = with TS2, TE2, TS3, TE3 concurrent
    tau2(TS2, TE2) = scan-area(TS2, TE2, Speed2, AreaA);
    tau3(TS3, TE3) = scan-area(TS3, TE3, Speed3, AreaB)
  where cons_tau1;
  tau4(TS4, TE4) = fly-to(TS4, TE4, Speed4, Dest4)
where cons_tau0

cons_tau0 = TS0 <= TS1 and TS1 < TE1 and TE1 <= TS4 and TS4 < TE4 and TE4 <= TE0
cons_tau1 = TS1 <= TS2 and TS2 < TE2 and TE2 <= TE1 and TS1 <= TS3 and TS3 < TE3 and TE3 <= TE1
