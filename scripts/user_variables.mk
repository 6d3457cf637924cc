# The variables a user gives make on its command line (README.md), checked by the top Makefile
# and Makefile.cases alike. A misspelt one was taken as a new variable and ignored:
# HEADFROM_SCAN= ran the generated head, CASE= printed the help with exit 0.
USER_VARIABLES := case HEADFORM_SCAN RESPIRATOR_SCAN LANDMARKS HEADFORM_UNIT RESPIRATOR_UNIT BUILD JOBS
$(foreach v,$(.VARIABLES),$(if $(filter command line,$(origin $(v))),$(if $(filter $(v),$(USER_VARIABLES)),,\
  $(error unknown variable $(v)=$($(v)): make takes $(USER_VARIABLES) (see make help)))))

# BUILD only from the command line (or the top Makefile, which passes its own): a shell that had
# BUILD set for something else built and ran the cases there.
ifneq ($(origin BUILD),command line)
BUILD := build
endif

# A case named on the command line is checked here, before the top Makefile installs or builds
# anything: a misspelt case (case=medium_onsize) cost the whole install and compile before
# Makefile.cases refused it. A name with a folder in it (case=../cases/x) put the case's outputs
# outside build/cases/.
ifneq ($(case),)
ifneq ($(words $(case))$(notdir $(case)),1$(case))
$(error case '$(case)': a case is a file name of data/cases/ without .mk, e.g. medium_onesize)
endif
ifeq ($(wildcard data/cases/$(case).mk),)
$(error unknown case '$(case)': no data/cases/$(case).mk)
endif
endif
