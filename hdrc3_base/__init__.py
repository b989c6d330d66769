"""hdrc3_base: the bottom layer every hdrc3 package may import and that imports none of them."""
