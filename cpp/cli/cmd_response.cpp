// `pcsim response` (placeholder until the continuation lands).
