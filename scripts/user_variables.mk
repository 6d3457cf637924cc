# The variables a user gives make on its command line (README.md), checked by the top Makefile
# and Makefile.cases alike. A misspelt one was taken as a new variable and ignored:
# HEADFROM_SCAN= ran the generated head, CASE= printed the help with exit 0.
# A case's placement and strap settings (Makefile.cases passes each to straps and assemble alike).
CASE_SETTINGS := STRAP_LENGTH_MM STRAP_WIDTH_MM STRAP_THICKNESS_MM GAP_MM BRIDGE_OFFSET_MM MAX_RIM_OFF_MM
USER_VARIABLES := case HEADFORM_SCAN RESPIRATOR_SCAN LANDMARKS HEADFORM_UNIT RESPIRATOR_UNIT BUILD JOBS $(CASE_SETTINGS)
$(foreach v,$(.VARIABLES),$(if $(filter command line,$(origin $(v))),$(if $(filter $(v),$(USER_VARIABLES)),,\
  $(error unknown variable $(v)=$($(v)): make takes $(USER_VARIABLES) (see make help)))))

# BUILD only from the command line (or the top Makefile, which passes its own): a shell that had
# BUILD set for something else built and ran the cases there.
ifneq ($(origin BUILD),command line)
BUILD := build
endif
# The build folder is removed whole by make clean and written into by every rule: a BUILD with a
# space in it ("/home/me/My Projects/build") had the case rules run rm -rf on /home/me/My, and
# make clean too (sweep P); the source folder or one above it would go with make clean.
ifneq ($(words $(BUILD)),1)
$(error BUILD='$(BUILD)': make cannot take a folder with a space in it (or none); give one without)
endif
ifneq ($(findstring ',$(BUILD))$(findstring ",$(BUILD))$(findstring $$,$(BUILD)),)
$(error BUILD=$(BUILD): make cannot take a folder with a quote or a $$ in it; give one without)
endif
ifneq ($(filter $(patsubst %/,%,$(abspath $(BUILD)))/%,$(CURDIR)/),)
$(error BUILD=$(BUILD): is this source folder or holds it (make clean would remove it); give a folder of its own, such as build)
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

# The user's files, checked before anything is set up (and, through the top Makefile, before
# anything is installed or built), and named by their real path, so the same
# file spelt two ways is one input. Each failure was found only by a stage, after the case's
# folders were rearranged for it: an empty value (an unset shell variable) fed the chain its own
# inputs.txt, a missing file left an empty head/ that then replaced head.previous, and a path
# with a space or a quote broke the rules (make splits prerequisites at spaces). A folder or an
# empty file reached the stage, after the case's old outputs had been removed (sweep J).
user_file = $(if $(filter-out undefined,$(origin $(1))),\
  $(if $(strip $($(1))),,$(error $(1) is empty: give a file, or leave $(1) out for the default))\
  $(if $(word 2,$($(1)))$(findstring ',$($(1)))$(findstring ",$($(1))),\
    $(error $(1)='$($(1))': make cannot take a path with a space or a quote; link or copy the file to one without))\
  $(if $(wildcard $($(1))),,$(error $(1)=$($(1)): no such file))\
  $(if $(wildcard $($(1))/.),$(error $(1)=$($(1)): is a folder, give a file))\
  $(if $(shell [ -f '$($(1))' ] || echo no),$(error $(1)=$($(1)): not a regular file (a device, pipe or socket)))\
  $(if $(shell [ -s '$($(1))' ] || echo empty),$(error $(1)=$($(1)): the file is empty))\
  $(eval override $(1) := $(realpath $($(1))))$(eval USER_FILES += $(1)))
$(call user_file,HEADFORM_SCAN)
$(call user_file,RESPIRATOR_SCAN)
$(call user_file,LANDMARKS)

# The case settings: taken from the command line or the case file, never from the shell's
# environment (as BUILD: a GAP_MM exported for something else would change every model), and each
# a number (its range is the stage program's to check: straps --help). Checked again by
# Makefile.cases after the case file is read.
$(foreach v,$(CASE_SETTINGS),$(if $(filter environment%,$(origin $(v))),$(eval undefine $(v))))
case_setting = $(if $(filter-out undefined,$(origin $(1))),\
  $(if $(word 2,$($(1)))$(findstring ',$($(1)))$(findstring ",$($(1))),\
    $(error $(1)='$($(1))': expected one number in mm),\
  $(if $(shell printf '%s\n' '$($(1))' | grep -Exq -- '-?[0-9]+([.][0-9]*)?' || echo bad),\
    $(error $(1)=$($(1)): expected a number in mm (make help)))))
$(foreach v,$(CASE_SETTINGS),$(call case_setting,$(v)))
