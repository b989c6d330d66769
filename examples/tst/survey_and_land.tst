# One RMAX takes off from pad H1, hovers 10 s, scans the south field, looks at the town hall
# and lands back at H1 within 15 minutes; the scan starts no earlier than 60 s into the mission.
world revinge
agents uav0

area SouthField = polygon((-170, -185), (-60, -185), (-60, -130), (-170, -130))
point TownHall = town_hall at 0
point PadH1 = H1 at 20

mission(P, TS, TE) = with T1, T2, T3, T4, T5, T6, T7, T8, T9, T10, T11, T12 sequence
  up(T1, T2) = take-off(T1, T2);
  settle(T3, T4) = hover(T3, T4, 10);
  survey(T5, T6) = scan-area(T5, T6, SurveySpeed, SouthField, 25);
  look(T7, T8) = look-at(T7, T8, TownHall);
  back(T9, T10) = fly-to(T9, T10, 8, PadH1);
  down(T11, T12) = land(T11, T12, 0)
where P = uav0 and TS = 0 and TE <= 900 and T5 >= 60 and SurveySpeed <= 6
