# The conventions every subcommand shares (README, "Command-line conventions and exit status"):
# usage errors exit 2, refused options 1, "--" ends the options, --help and --version exit 0.
run npf
run npf frobnicate
run npf convert
run npf convert --bogus x.bsdf -o y.exr
run npf convert x.bsdf -o
run npf info --json -- -not-an-option.bsdf
run npf eval --plain --help
# The conversion settings' help comes from the settings table: it changes only with a row.
run npf convert --help
