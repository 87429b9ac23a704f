"""Chart inputs, S-52 rendering, segmentation, gridding and swelling."""
