# Example 6.1 of the HDRC3 chapter as a delegation request (section 10): the same mission as
# example_6_1.tst, but no node names its agent. `hdrc3 delegate` lets the agents' constraint
# servers bid for the nodes and binds every P to the winner of each node's auction.
world revinge
agents uav0, uav1, uav2

area AreaA = polygon((-280, -40), (-160, -40), (-160, 40), (-280, 40))
area AreaB = polygon((-180, -120), (-80, -120), (-80, -60), (-180, -60))
point Dest4 = town_square at 40

tau0(P0, TS0, TE0) = with TS1, TE1, P4, TS4, TE4 sequence
  tau1(TS1, TE1) = with P2, TS2, TE2, P3, TS3, TE3 concurrent
    tau2(P2, TS2, TE2) = scan-area(TS2, TE2, Speed2, AreaA);
    tau3(P3, TS3, TE3) = scan-area(TS3, TE3, Speed3, AreaB)
  where cons_tau1;
  tau4(P4, TS4, TE4) = fly-to(TS4, TE4, Speed4, Dest4)
where cons_tau0 and TE0 <= 900

cons_tau0 = TS0 <= TS1 and TS1 < TE1 and TE1 <= TS4 and TS4 < TE4 and TE4 <= TE0
cons_tau1 = TS1 <= TS2 and TS2 < TE2 and TE2 <= TE1 and TS1 <= TS3 and TS3 < TE3 and TE3 <= TE1
