int voroclip_probe() { return 0; }
